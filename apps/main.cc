// SPDX-License-Identifier: MIT
// `dsm`: direct sparse mapping from the command line. Exit codes: 0 success, 2 bad input
// (files, calibration, options), 1 an unexpected internal error.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <string>

#include "apps/commands.h"
#include "dsm/util/check.h"
#include "dsm/util/version.h"

int main(int argc, char** argv) {
  CLI::App app{"dsm: monocular visual SLAM by Direct Sparse Mapping"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("dsm ") + dsm::kVersion);
  std::map<CLI::App*, dsm::cli::Command> commands;
  const auto add = [&](const char* name, const char* help, auto adder) {
    CLI::App* sub = app.add_subcommand(name, help);
    commands[sub] = adder(*sub);
  };
  add("run", "Run SLAM on a dataset; writes trajectories, statistics and evaluation", dsm::cli::AddRun);
  add("info", "Describe a dataset: format, frames, camera, ground truth", dsm::cli::AddInfo);
  add("eval", "Compare an estimated trajectory with a reference (APE, RPE)", dsm::cli::AddEval);
  add("gt-check", "Check a dataset's ground truth against its images (epipolar distance of tracked corners)",
      dsm::cli::AddGtCheck);
  add("synth", "Render a synthetic sequence with exact ground truth", dsm::cli::AddSynth);
  add("calibrate", "Calibrate a camera from views of a checkerboard; writes the camera.yaml dsm run reads",
      dsm::cli::AddCalibrate);
  add("report", "Rebuild report.html (map, trajectory, plots; one self-contained page) from a run's output folder",
      dsm::cli::AddReport);
  add("map", "Map files (dsm run --save-map): `dsm map info FILE` describes one", dsm::cli::AddMap);
  add("vocabulary", "Train the vocabulary of visual words that loop detection uses, on rendered scenes",
      dsm::cli::AddVocabulary);
  add("damage", "Copy a EuRoC recording with bad frames spliced in (black, noise, a hand over the lens, damaged files)",
      dsm::cli::AddDamage);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    for (auto& [sub, run] : commands) {
      if (sub->parsed()) return run();
    }
  } catch (const dsm::InputError& e) {
    std::fprintf(stderr, "dsm: error: %s\n", e.what());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    // A path of the user's that the file system refuses (too long, no permission, ...).
    std::fprintf(stderr, "dsm: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dsm: internal error: %s\n", e.what());
    return 1;
  }
  return 2;
}
