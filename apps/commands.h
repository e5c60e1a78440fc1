// SPDX-License-Identifier: MIT
// The `dsm` subcommands. Each Add* registers its options on the app and returns the function that
// runs it; the function returns the process exit code and throws InputError on bad input.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

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

// --calib / --groundtruth / --time-offset: a video file as the dataset (io/video_dataset.h).
struct VideoArgs {
  std::string calib, ground_truth;
  double time_offset_s = 0.0;
};
void AddVideoOptions(CLI::App& app, VideoArgs* args);
// A dataset folder, or a video file (by its name's ending) with VideoArgs; throws InputError when
// the video options are given for a folder.
Dataset OpenInput(const std::string& path, const GtArgs& gt, const VideoArgs& video);

}  // namespace dsm::cli
