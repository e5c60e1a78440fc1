// SPDX-License-Identifier: MIT
#include "dsm/io/yaml_file.h"

#include "dsm/util/parse.h"

namespace dsm {

YAML::Node LoadYamlFile(const std::filesystem::path& path) {
  // Anything that reads as text but a folder (which opens as a stream and fails on the first
  // read): a file, /dev/null for no settings, a pipe (`--config <(printf ...)`).
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw InputError(path.string() + ": file not found");
  if (std::filesystem::is_directory(status)) throw InputError(path.string() + ": a folder, not a YAML file");
  std::string text;
  for (const auto& line : ReadLines(path)) {
    if (line.rfind("%YAML", 0) == 0) continue;
    text += line + "\n";
  }
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(path.string() + ": YAML error: " + e.what());
  }
}

YAML::Node LoadYamlMapping(const std::filesystem::path& path) {
  const YAML::Node node = LoadYamlFile(path);
  if (!node.IsMap()) throw InputError(path.string() + ": expected a YAML mapping");
  return node;
}

std::string KeyName(const YAML::Node& key, const std::filesystem::path& path) {
  if (!key.IsScalar()) {
    throw InputError(path.string() + ": line " + std::to_string(key.Mark().line + 1) +
                     ": a key must be a plain name, not a sequence or mapping");
  }
  return key.Scalar();
}

}  // namespace dsm
