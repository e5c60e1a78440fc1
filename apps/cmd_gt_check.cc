// SPDX-License-Identifier: MIT
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "dsm/eval/ground_truth_check.h"
#include "dsm/util/check.h"

namespace dsm::cli {

void AddGtOptions(CLI::App& app, GtArgs* args) {
  app.add_option("--gt-frame", args->frame,
                 "EuRoC ground-truth rows are body poses (x T_BS, the ASL default) or camera poses: body | camera");
  app.add_option("--gt-quaternion", args->quaternion, "EuRoC ground-truth quaternion sense: hamilton | jpl");
}

GroundTruthConvention GtArgs::Parse() const {
  return {ParseGtFrame(frame, "--gt-frame"), ParseGtQuaternion(quaternion, "--gt-quaternion")};
}

Command AddGtCheck(CLI::App& app) {
  struct Args {
    std::string dataset, json;
    GtCheckOptions options;
  };
  auto a = std::make_shared<Args>();
  app.add_option("DATASET", a->dataset, "Dataset folder with ground truth")->required();
  app.add_option("--gap", a->options.gap, "Frames between the two images of a pair (default 5)");
  app.add_option("--pairs", a->options.max_pairs, "Frame pairs, spread over the sequence (default 100)");
  app.add_option("--json", a->json, "Write the table as JSON to this file");
  return [a] {
    a->options.Validate();
    // Only EuRoC ground truth has several readings; other formats are checked as they are.
    const Dataset base = OpenDataset(a->dataset);
    if (!base.HasGroundTruth()) throw InputError(a->dataset + ": the dataset has no ground truth");
    const std::vector<GroundTruthConvention> conventions =
        base.format == "euroc" ? AllGroundTruthConventions() : std::vector<GroundTruthConvention>{{}};
    const std::vector<PairTracks> tracks = TrackPairs(base, a->options);
    const double focal = base.camera.fx;
    nlohmann::json out = nlohmann::json::array();
    std::printf("%-16s %6s %8s %10s %8s\n", "ground truth", "pairs", "tracks", "median px", "p90 px");
    std::string best;
    double best_median = 0.0;
    for (const GroundTruthConvention& c : conventions) {
      const Trajectory gt = c.IsDefault() ? base.ground_truth : OpenDataset(a->dataset, c).ground_truth;
      const EpipolarStats s = EpipolarError(tracks, base, gt, a->options, focal);
      const std::string name = base.format == "euroc" ? c.Name() : "as stored";
      std::printf("%-16s %6zu %8zu %10.3f %8.3f\n", name.c_str(), s.pairs, s.tracks, s.median_px, s.p90_px);
      out.push_back({{"ground_truth", name}, {"pairs", s.pairs}, {"tracks", s.tracks}, {"median_px", s.median_px},
                     {"p90_px", s.p90_px}});
      if (s.tracks > 0 && (best.empty() || s.median_px < best_median)) {
        best = name;
        best_median = s.median_px;
      }
    }
    if (best.empty()) throw InputError(a->dataset + ": no frame pair with ground truth and enough motion to check");
    std::printf("images agree best with: %s (median epipolar distance %.3f px)\n", best.c_str(), best_median);
    if (!a->json.empty()) {
      std::ofstream f(a->json);
      f << nlohmann::json{{"readings", out}, {"best", best}}.dump(2) << "\n";
      if (!f) throw InputError(a->json + ": cannot write file");
    }
    return 0;
  };
}

}  // namespace dsm::cli
