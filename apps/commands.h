// SPDX-License-Identifier: MIT
// The `dsm` subcommands. Each Add* registers its options on the app and returns the function that
// runs it; the function returns the process exit code and throws InputError on bad input.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace dsm::cli {

using Command = std::function<int()>;

Command AddInfo(CLI::App& app);
Command AddEval(CLI::App& app);
Command AddSynth(CLI::App& app);
Command AddRun(CLI::App& app);

}  // namespace dsm::cli
