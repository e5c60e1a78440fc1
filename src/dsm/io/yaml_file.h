// SPDX-License-Identifier: MIT
// The user's YAML files (camera calibration, options): every yaml-cpp error becomes an InputError
// naming the file and the key, so that no malformed file escapes as an internal error.
#pragma once

#include <filesystem>
#include <string>

#include <yaml-cpp/yaml.h>

#include "dsm/util/check.h"

namespace dsm {

// The file's document (a null node for an empty file). OpenCV-style files start with a
// "%YAML:1.0" directive that yaml-cpp rejects: it is dropped.
YAML::Node LoadYamlFile(const std::filesystem::path& path);

// The file's document, which must be a mapping (InputError naming the file otherwise).
YAML::Node LoadYamlMapping(const std::filesystem::path& path);

// A mapping key as a name; keys that are sequences or mappings ("[a]: 1") are rejected.
std::string KeyName(const YAML::Node& key, const std::filesystem::path& path);

// Value of `key` in the mapping `node`, converted to T; throws InputError when missing or of
// another type.
template <typename T>
T Get(const YAML::Node& node, const std::string& key, const std::filesystem::path& path) {
  const YAML::Node value = node[key];
  if (!value) throw InputError(path.string() + ": missing key '" + key + "'");
  try {
    return value.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(path.string() + ": key '" + key + "' has the wrong type");
  }
}

}  // namespace dsm
