// SPDX-License-Identifier: MIT
// The `dsm` subcommands. Each Add* registers its options on the app and returns the function that
// runs it; the function returns the process exit code and throws InputError on bad input.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "dsm/bag/bag_dataset.h"
#include "dsm/io/dataset.h"

namespace dsm::cli {

using Command = std::function<int()>;

Command AddInfo(CLI::App& app);
Command AddEval(CLI::App& app);
Command AddSynth(CLI::App& app);
Command AddRun(CLI::App& app);
Command AddGtCheck(CLI::App& app);
Command AddReport(CLI::App& app);
Command AddDamage(CLI::App& app);
Command AddMap(CLI::App& app);
Command AddVocabulary(CLI::App& app);
Command AddCalibrate(CLI::App& app);

// --gt-frame / --gt-quaternion: how EuRoC ground-truth rows are read (see io/dataset.h).
struct GtArgs {
  std::string frame = "body", quaternion = "hamilton";
  GroundTruthConvention Parse() const;  // Throws InputError naming the option.
};
void AddGtOptions(CLI::App& app, GtArgs* args);

// What a video file or a recording needs besides its path:
//   video      --calib, --groundtruth, --time-offset (io/video_dataset.h)
//   recording  --topic, --calib, --gt-topic, --gt-frames (bag/bag_dataset.h)
struct InputArgs {
  std::string calib, ground_truth;
  double time_offset_s = 0.0;
  std::string topic, gt_topic;
  std::vector<std::string> gt_frames;
};
void AddInputOptions(CLI::App& app, InputArgs* args);
// A recording's options (bag/bag_dataset.h).
BagInput BagInputFrom(const InputArgs& args, const GtArgs& gt);
// A dataset folder, a video file or a recording (by its name), with InputArgs; throws InputError
// when an option is given for an input it does not apply to.
Dataset OpenInput(const std::string& path, const GtArgs& gt, const InputArgs& video);

}  // namespace dsm::cli
