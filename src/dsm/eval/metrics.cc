// SPDX-License-Identifier: MIT
#include "dsm/eval/metrics.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "dsm/geometry/umeyama.h"
#include "dsm/util/check.h"

namespace dsm {

ErrorStats ComputeStats(std::vector<double> e) {
  if (e.empty()) throw InputError("no errors to summarise: the trajectories have no matching poses");
  ErrorStats s;
  s.count = e.size();
  const double n = static_cast<double>(e.size());
  double sum = 0, sum_sq = 0;
  for (double v : e) {
    sum += v;
    sum_sq += v * v;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  double var = 0;
  for (double v : e) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);
  std::sort(e.begin(), e.end());
  s.min = e.front();
  s.max = e.back();
  const size_t mid = e.size() / 2;
  s.median = e.size() % 2 ? e[mid] : 0.5 * (e[mid - 1] + e[mid]);
  return s;
}

Alignment ParseAlignment(const std::string& name, const std::string& where) {
  if (name == "none") return Alignment::kNone;
  if (name == "se3") return Alignment::kSE3;
  if (name == "sim3") return Alignment::kSim3;
  throw InputError(where + ": unknown alignment '" + name + "' (expected none, se3 or sim3)");
}

void EvalOptions::Validate() const {
  if (!(max_dt_s >= 0.0) || !std::isfinite(max_dt_s)) throw InputError("--max-dt must be a non-negative number of seconds");
  if (rpe_delta && !(*rpe_delta > 0.0)) throw InputError("--rpe-delta must be positive");
  if (rpe_delta && rpe_unit == RpeUnit::kFrames && std::floor(*rpe_delta) != *rpe_delta)
    throw InputError("--rpe-delta must be a whole number of frames with --rpe-unit f");
}

namespace {

std::vector<std::pair<size_t, size_t>> RpePairs(const std::vector<SE3d>& est, double delta, RpeUnit unit) {
  std::vector<size_t> ids;
  if (unit == RpeUnit::kFrames) {
    const size_t step = static_cast<size_t>(delta);
    for (size_t i = 0; i < est.size(); i += step) ids.push_back(i);
  } else {
    double path = 0.0;
    for (size_t i = 0; i < est.size(); ++i) {
      if (i > 0) path += (est[i].Translation() - est[i - 1].Translation()).norm();
      if (path >= delta) {
        ids.push_back(i);
        path = 0.0;
      }
    }
  }
  std::vector<std::pair<size_t, size_t>> pairs;
  for (size_t k = 1; k < ids.size(); ++k) pairs.emplace_back(ids[k - 1], ids[k]);
  return pairs;
}

Association Associate(const Trajectory& ref, const Trajectory& est, const EvalOptions& options) {
  return ref.HasStamps() && est.HasStamps() ? AssociateByTime(ref, est, options.max_dt_s)
                                            : AssociateByIndex(ref, est, "the reference", "the estimate");
}

}  // namespace

Trajectory ReferenceInEstimateFrame(const Trajectory& ref, const Trajectory& est, const EvalResult& result,
                                    const EvalOptions& options) {
  const Association assoc = Associate(ref, est, options);
  const Sim3d est_from_ref = result.ref_from_est.Inverse();
  Trajectory out;
  for (size_t k = 0; k < assoc.size(); ++k) {
    const SE3d& pose = ref.poses[assoc.ref_index[k]];
    const size_t e = assoc.est_index[k];
    out.Add(est.HasStamps() ? est.stamps_ns[e] : static_cast<int64_t>(e),
            SE3d(est_from_ref.So3() * pose.So3(), est_from_ref * pose.Translation()));
  }
  return out;
}

EvalResult Evaluate(const Trajectory& ref, const Trajectory& est, const EvalOptions& options) {
  options.Validate();
  if (ref.empty()) throw InputError("the reference trajectory is empty");
  if (est.empty()) throw InputError("the estimated trajectory is empty");
  const Association assoc = Associate(ref, est, options);
  if (assoc.size() == 0) {
    throw InputError("no poses associate within --max-dt " + std::to_string(options.max_dt_s) +
                     " s: do the trajectories share a time base?");
  }
  std::vector<SE3d> ref_poses, est_poses;
  std::vector<Eigen::Vector3d> ref_pos, est_pos;
  for (size_t k = 0; k < assoc.size(); ++k) {
    ref_poses.push_back(ref.poses[assoc.ref_index[k]]);
    est_poses.push_back(est.poses[assoc.est_index[k]]);
    ref_pos.push_back(ref_poses.back().Translation());
    est_pos.push_back(est_poses.back().Translation());
  }

  EvalResult result;
  result.pairs = assoc.size();
  if (options.fixed_alignment) {
    result.ref_from_est = *options.fixed_alignment;
  } else if (options.align != Alignment::kNone) {
    result.ref_from_est = UmeyamaAlignment(est_pos, ref_pos, options.align == Alignment::kSim3);
  }
  // Aligned estimate: rotation R R_i, position s R t_i + t.
  const Sim3d& S = result.ref_from_est;
  for (auto& pose : est_poses) pose = SE3d(S.So3() * pose.So3(), S * pose.Translation());

  std::vector<double> ape(assoc.size());
  for (size_t k = 0; k < assoc.size(); ++k) {
    ape[k] = (ref_poses[k].Translation() - est_poses[k].Translation()).norm();
  }
  result.ape = ComputeStats(std::move(ape));

  if (options.rpe_delta) {
    std::vector<double> rpe;
    for (const auto& [i, j] : RpePairs(est_poses, *options.rpe_delta, options.rpe_unit)) {
      const SE3d ref_rel = ref_poses[i].Inverse() * ref_poses[j];
      const SE3d est_rel = est_poses[i].Inverse() * est_poses[j];
      rpe.push_back((ref_rel.Inverse() * est_rel).Translation().norm());
    }
    if (rpe.empty()) throw InputError("--rpe-delta is longer than the trajectory: no RPE pairs");
    result.rpe = ComputeStats(std::move(rpe));
  }
  return result;
}

nlohmann::json ToJson(const ErrorStats& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
          {"std", s.std},   {"min", s.min},   {"max", s.max}};
}

nlohmann::json ToJson(const EvalResult& r) {
  const Sim3d& S = r.ref_from_est;
  const Eigen::Quaterniond& q = S.So3().Quaternion();
  nlohmann::json j = {{"ape", ToJson(r.ape)},
                      {"pairs", r.pairs},
                      {"scale", S.Scale()},
                      {"alignment",
                       {{"rotation_xyzw", {q.x(), q.y(), q.z(), q.w()}},
                        {"translation", {S.Translation().x(), S.Translation().y(), S.Translation().z()}},
                        {"scale", S.Scale()}}}};
  if (r.rpe) {
    j["rpe"] = ToJson(*r.rpe);
    j["rpe"]["pairs"] = r.rpe->count;
  }
  return j;
}

Sim3d AlignmentFromJson(const nlohmann::json& j, const std::string& where) {
  const nlohmann::json* a = nullptr;
  if (j.is_object() && j.contains("alignment")) {
    a = &j["alignment"];
  } else if (j.is_object() && j.contains("keyframes") && j["keyframes"].is_object() &&
             j["keyframes"].contains("alignment")) {
    a = &j["keyframes"]["alignment"];
  }
  if (a == nullptr) throw InputError(where + ": no \"alignment\" (nor \"keyframes\".\"alignment\") in it");
  const auto numbers = [&](const char* key, size_t n) {
    if (!a->is_object() || !a->contains(key) || !(*a)[key].is_array() || (*a)[key].size() != n)
      throw InputError(where + ": alignment." + key + " must be a list of " + std::to_string(n) + " numbers");
    std::vector<double> v;
    for (const nlohmann::json& x : (*a)[key]) {
      if (!x.is_number() || !std::isfinite(x.get<double>()))
        throw InputError(where + ": alignment." + key + " must hold finite numbers");
      v.push_back(x.get<double>());
    }
    return v;
  };
  const std::vector<double> q = numbers("rotation_xyzw", 4), t = numbers("translation", 3);
  if (!a->contains("scale") || !(*a)["scale"].is_number() || !((*a)["scale"].get<double>() > 0.0) ||
      !std::isfinite((*a)["scale"].get<double>())) {
    throw InputError(where + ": alignment.scale must be a positive number");
  }
  const Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
  if (std::abs(rotation.norm() - 1.0) > 1e-6) throw InputError(where + ": alignment.rotation_xyzw is not a unit quaternion");
  return Sim3d((*a)["scale"].get<double>(), SO3d(rotation), Eigen::Vector3d(t[0], t[1], t[2]));
}

}  // namespace dsm
