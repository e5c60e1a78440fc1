// SPDX-License-Identifier: MIT
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "apps/commands.h"
#include "dsm/run/map_run.h"
#include "dsm/eval/metrics.h"
#include "dsm/io/dataset.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"

namespace dsm::cli {

namespace {

struct EvalArgs {
  std::string ref, est, ref_format, est_format, align = "none", rpe_unit = "f", json, aligned, alignment_from;
  double max_dt = 0.01;
  double rpe_delta = 0.0;
};

Trajectory Load(const std::string& path, const std::string& format, const std::string& option) {
  if (std::filesystem::is_directory(path)) {
    // A recording (dsm run's inputs): its ground truth, camera poses as the run scores them.
    const Dataset dataset = OpenDataset(path);
    if (!dataset.HasGroundTruth()) throw InputError(path + ": the recording has no ground truth");
    return dataset.ground_truth;
  }
  const TrajectoryFormat f = format.empty() ? DetectTrajectoryFormat(path) : ParseTrajectoryFormat(format, option);
  return ReadTrajectory(path, f);
}

void PrintStats(const char* name, const ErrorStats& s, size_t pairs) {
  std::printf("%s (m, %zu pairs): rmse %.6f  mean %.6f  median %.6f  std %.6f  min %.6f  max %.6f\n", name, pairs,
              s.rmse, s.mean, s.median, s.std, s.min, s.max);
}

}  // namespace

Command AddEval(CLI::App& app) {
  auto a = std::make_shared<EvalArgs>();
  app.add_option("--ref", a->ref, "Reference trajectory file, or a recording's folder (its ground truth)")->required();
  app.add_option("--est", a->est, "Estimated trajectory file")->required();
  app.add_option("--ref-format", a->ref_format, "tum | euroc | kitti (detected when omitted)");
  app.add_option("--est-format", a->est_format, "tum | euroc | kitti (detected when omitted)");
  app.add_option("--align", a->align, "none | se3 | sim3 (Umeyama, estimate onto reference)");
  app.add_option("--alignment-from", a->alignment_from,
                 "Apply the alignment of this evaluation (a run's eval.json, or --json of dsm eval) instead of "
                 "fitting one: a later session (dsm run --load-map) scored in the earlier one's frame and scale");
  app.add_option("--max-dt", a->max_dt, "Largest timestamp difference of an associated pair, seconds");
  app.add_option("--rpe-delta", a->rpe_delta, "Compute RPE over this distance (see --rpe-unit)");
  app.add_option("--rpe-unit", a->rpe_unit, "f (frames) | m (metres along the estimate's path)");
  app.add_option("--json", a->json, "Write the results as JSON to this file");
  app.add_option("--aligned", a->aligned, "Write the estimate after the alignment to this file (TUM; to plot it)");
  return [a] {
    EvalOptions options;
    options.align = ParseAlignment(a->align, "--align");
    options.max_dt_s = a->max_dt;
    if (a->rpe_unit != "f" && a->rpe_unit != "m") throw InputError("--rpe-unit: expected f or m, got '" + a->rpe_unit + "'");
    options.rpe_unit = a->rpe_unit == "m" ? RpeUnit::kMeters : RpeUnit::kFrames;
    if (a->rpe_delta != 0.0) options.rpe_delta = a->rpe_delta;
    options.Validate();
    if (!a->alignment_from.empty()) {
      std::ifstream in(a->alignment_from);
      if (!in) throw InputError(a->alignment_from + ": cannot read file");
      const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
      if (j.is_discarded()) throw InputError(a->alignment_from + ": not valid JSON");
      options.fixed_alignment = AlignmentFromJson(j, a->alignment_from);
    }
    const Trajectory ref = Load(a->ref, a->ref_format, "--ref-format");
    const Trajectory est = Load(a->est, a->est_format, "--est-format");
    const EvalResult result = Evaluate(ref, est, options);
    PrintStats("APE", result.ape, result.pairs);
    if (options.align == Alignment::kSim3 || options.fixed_alignment) std::printf("scale %.9f\n", result.ref_from_est.Scale());
    if (result.rpe) PrintStats("RPE", *result.rpe, result.rpe->count);
    if (!a->aligned.empty()) {
      // Positions through the similarity, orientations through its rotation.
      Trajectory aligned = est;
      for (SE3d& pose : aligned.poses)
        pose = SE3d(result.ref_from_est.So3() * pose.So3(), result.ref_from_est * pose.Translation());
      WriteTumTrajectory(a->aligned, aligned);
    }
    if (!a->json.empty()) WriteJson(a->json, ToJson(result));
    return 0;
  };
}

}  // namespace dsm::cli
