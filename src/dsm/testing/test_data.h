// SPDX-License-Identifier: MIT
// Locations of test inputs: the shared real data beside the checkout and a per-test scratch folder;
// commands run as a user runs them.
#pragma once

#include <filesystem>
#include <string>

namespace dsm::testing {

// The shared data folder (`../shared/data` beside the checkout, or $DSM_SHARED_DATA).
std::filesystem::path SharedDataDir();

// A fresh, empty folder under the build tree for files a test writes.
std::filesystem::path ScratchDir(const std::string& name);

// Writes `text` to `path` (creating parent folders) and returns the path.
std::filesystem::path WriteText(const std::filesystem::path& path, const std::string& text);

// A shell command run to its end: its exit code (-1: it did not exit) and its output, stdout and
// stderr together.
struct CommandResult {
  int code = -1;
  std::string output;
};
CommandResult RunCommand(const std::string& command);

}  // namespace dsm::testing
