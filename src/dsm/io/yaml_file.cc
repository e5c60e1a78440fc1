// SPDX-License-Identifier: MIT
#include "dsm/io/yaml_file.h"

#include "dsm/util/parse.h"

namespace dsm {

YAML::Node LoadYamlFile(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path.string() + ": file not found");
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

std::string KeyName(const YAML::Node& key, const std::filesystem::path& path) {
  if (!key.IsScalar()) {
    throw InputError(path.string() + ": line " + std::to_string(key.Mark().line + 1) +
                     ": a key must be a plain name, not a sequence or mapping");
  }
  return key.Scalar();
}

}  // namespace dsm
