// SPDX-License-Identifier: MIT
// The command line tests' way to run `dsm` (DSM_CLI_PATH, the binary the build made) and read its
// output.
#pragma once

#include <string>

#include "dsm/testing/test_data.h"

namespace dsm::testing {

using Result = CommandResult;

inline Result RunDsm(const std::string& args) { return RunCommand(std::string(DSM_CLI_PATH) + " " + args); }

inline bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace dsm::testing
