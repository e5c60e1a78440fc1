// SPDX-License-Identifier: MIT
#include "dsm/optimization/pba_problem.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "dsm/optimization/pba_models.h"
#include "dsm/optimization/pba_selection.h"

namespace dsm::internal {

Problem::Problem(Map* map, const PinholeCamera& camera, const std::vector<int>& active, const std::vector<int>& held,
                 const PbaOptions& options)
    : map_(map), camera_(camera), options_(options) {
  PbaSelection selection = SelectPbaProblem(*map, active, held, options);
  for (size_t c = 0; c < selection.cams.size(); ++c) {
    Keyframe& k = map->keyframe(selection.cams[c]);
    if (!selection.fixed[c]) k.most_pba_links = std::max(k.most_pba_links, selection.links[c]);
  }
  cams_ = std::move(selection.cams);
  fixed_ = std::move(selection.fixed);
  num_obs_ = selection.num_observations;
  points_.reserve(selection.points.size());
  for (const PbaSelection::PointObservations& po : selection.points) {
    PointState ps;
    ps.id = po.id;
    ps.host = po.host;
    ps.frozen = map->keyframe(cams_[po.host]).frozen;
    for (int t : po.targets) ps.obs.push_back({t});
    points_.push_back(std::move(ps));
  }
  map->LoadPyramids(cams_);
  models_.resize(cams_.size());
  for (size_t c = 0; c < cams_.size(); ++c) models_[c] = map->keyframe(cams_[c]).error_model;
  IndexPairs();
}

void Problem::SetLevel(int level) {
  level_ = level;
  level_camera_ = camera_.AtLevel(level);
  const float scale = 1.f / static_cast<float>(1 << level);
  tbb::parallel_for(size_t{0}, points_.size(), [&](size_t i) {
    PointState& ps = points_[i];
    const Point& p = map_->point(ps.id);
    const Eigen::Vector2f px((p.pixel.x() + 0.5f) * scale - 0.5f, (p.pixel.y() + 0.5f) * scale - 0.5f);
    ps.patch_ok = SampleHostPatch(map_->keyframe(cams_[ps.host]).Pyramid(), level, px, map_->interpolation(), &ps.patch);
    for (ObsState& o : ps.obs) o.x = o.y = -1;
  });
}

// Fits each camera's error model to the current residuals of the observations in it. Residuals
// are gathered in parallel chunks and concatenated in point order; the fits run in parallel per
// camera: the result is that of the sequential loop.
void Problem::FitModels() {
  UpdatePairs();
  const size_t n = cams_.size();
  std::vector<std::vector<std::vector<float>>> chunk_residuals(kChunks, std::vector<std::vector<float>>(n));
  tbb::parallel_for(0, kChunks, [&](int chunk) {
    const size_t begin = points_.size() * chunk / kChunks, end = points_.size() * (chunk + 1) / kChunks;
    for (size_t i = begin; i < end; ++i) {
      PointState& ps = points_[i];
      if (i + 1 < end) Prefetch(i + 1);
      if (!ps.patch_ok) continue;
      const bool skip_fit = !FitsModels(ps);
      for (ObsState& o : ps.obs) {
        ObservationResiduals res;
        if (!Evaluate(ps, o, Derivatives::kNone, &res)) continue;
        Remember(res, &o);
        if (skip_fit || TextureLostAtLevel(ps, res)) continue;
        std::vector<float>& out = chunk_residuals[chunk][o.target];
        for (int k = 0; k < kPatternSize; ++k) out.push_back(std::sqrt(res.weight_g[k]) * res.r[k]);
      }
    }
  });
  FitFromChunks(chunk_residuals);
}

// The same fit from the residuals of the accepted linearisation, which was made at the current
// state (a rejected step restores it): after the last level, without another pass.
void Problem::FitModelsFromLinearization() {
  const size_t n = cams_.size();
  std::vector<std::vector<std::vector<float>>> chunk_residuals(1, std::vector<std::vector<float>>(n));
  for (const PointState& ps : points_) {
    if (!ps.patch_ok || !FitsModels(ps)) continue;
    for (const ObsState& o : ps.obs) {
      if (!o.valid[current_] || o.texture_lost[current_]) continue;
      std::vector<float>& out = chunk_residuals[0][o.target];
      out.insert(out.end(), o.residual[current_].begin(), o.residual[current_].end());
    }
  }
  FitFromChunks(chunk_residuals);
}

// Builds the normal equations at the current state and accepts them as the linearisation the
// next step is taken from; returns the energy of the observations taking part.
double Problem::Linearize(NormalEquations* eq) {
  const Trial trial = LinearizeTrial(eq);
  Accept();
  return trial.energy;
}

Problem::Backup Problem::Save() const {
  Backup b;
  for (int id : cams_) {
    b.poses.push_back(map_->keyframe(id).cam_from_world);
    b.affine.push_back(map_->keyframe(id).affine);
  }
  for (const auto& ps : points_) b.idepth.push_back(map_->point(ps.id).idepth);
  return b;
}

void Problem::Restore(const Backup& b) {
  for (size_t c = 0; c < cams_.size(); ++c) {
    map_->keyframe(cams_[c]).cam_from_world = b.poses[c];
    map_->keyframe(cams_[c]).affine = b.affine[c];
  }
  for (size_t i = 0; i < points_.size(); ++i) map_->point(points_[i].id).idepth = b.idepth[i];
}

// Applies the step; returns true when it is below the convergence thresholds.
bool Problem::Apply(const Solution& step) {
  double max_rot = 0, max_trans = 0, max_a = 0, max_b = 0;
  for (size_t c = 0; c < cams_.size(); ++c) {
    if (fixed_[c]) continue;
    const CameraVector d = step.cameras.segment<kCameraParams>(kCameraParams * c);
    Keyframe& kf = map_->keyframe(cams_[c]);
    kf.cam_from_world = SE3d::Exp(d.head<6>()) * kf.cam_from_world;
    kf.affine.a += d(6);
    kf.affine.b += d(7);
    max_trans = std::max(max_trans, d.head<3>().norm());
    max_rot = std::max(max_rot, d.segment<3>(3).norm());
    max_a = std::max(max_a, std::abs(d(6)));
    max_b = std::max(max_b, std::abs(d(7)));
  }
  double mean_idepth = 0.0;
  for (size_t i = 0; i < points_.size(); ++i) {
    float& rho = map_->point(points_[i].id).idepth;
    if (!points_[i].frozen) rho = std::max(1e-4f, rho + static_cast<float>(step.points(i)));
    mean_idepth += rho;
  }
  mean_idepth /= std::max<size_t>(1, points_.size());
  return max_rot < options_.max_rotation_step && max_trans * mean_idepth < options_.max_translation_step &&
         max_a < options_.max_a_step && max_b < options_.max_b_step;
}

// After the PBA: marks observations with too many bad pixels (level 0, fitted models), by the
// residuals of the accepted linearisation (and the models fitted to them).
int Problem::MarkOutliers(int* texture_lost) {
  int removed = 0;
  *texture_lost = 0;
  for (PointState& ps : points_) {
    Point& p = map_->point(ps.id);
    for (size_t j = 0; j < ps.obs.size(); ++j) {
      const ObsState& o = ps.obs[j];
      int bad = kPatternSize;  // Unjudged or lost: removed.
      const bool judged = ps.patch_ok && o.valid[current_], lost = judged && o.texture_lost[current_];
      *texture_lost += lost;
      if (judged && !lost) {
        bad = 0;
        for (float r : o.residual[current_]) bad += models_[o.target].IsOutlier(r);
      }
      Observation* obs = p.FindObservation(cams_[o.target]);
      if (bad > options_.drop_outlier_ratio * kPatternSize) {
        obs->outlier = true;
        ++removed;
      }
    }
  }
  return removed;
}

// The host-target pairs the observations use, in (host, target) order, those with a free keyframe
// numbered as accumulator slots; and per chunk of points (fixed split) the slots its
// observations add to, numbered locally: a chunk's accumulators are only the ones it uses (a
// dense chunk x slot table would be tens of MB, zeroed on every linearisation).
void Problem::IndexPairs() {
  const int n = NumCameras();
  std::vector<int> index(static_cast<size_t>(n) * n, -1);
  for (const PointState& ps : points_)
    for (const ObsState& o : ps.obs) index[ps.host * n + o.target] = 0;
  int num_slots = 0;
  for (int h = 0; h < n; ++h)
    for (int t = 0; t < n; ++t) {
      if (index[h * n + t] < 0) continue;
      index[h * n + t] = static_cast<int>(pairs_.size());
      PairGeometry g;
      g.host = h;
      g.target = t;
      if (!(fixed_[h] && fixed_[t])) g.slot = num_slots++;
      pairs_.push_back(g);
    }
  slot_chunks_.assign(num_slots, {});
  chunk_slots_.assign(kChunks, 0);
  std::vector<int> local(num_slots, -1);
  for (int chunk = 0; chunk < kChunks; ++chunk) {
    const size_t begin = points_.size() * chunk / kChunks, end = points_.size() * (chunk + 1) / kChunks;
    std::vector<int> used;
    for (size_t i = begin; i < end; ++i)
      for (ObsState& o : points_[i].obs) {
        o.pair = index[points_[i].host * n + o.target];
        const int slot = pairs_[o.pair].slot;
        if (slot < 0) continue;
        if (local[slot] < 0) {
          local[slot] = chunk_slots_[chunk]++;
          used.push_back(slot);
          slot_chunks_[slot].emplace_back(chunk, local[slot]);
        }
        o.acc = local[slot];
      }
    for (int slot : used) local[slot] = -1;
  }
}

void Problem::UpdatePairs() {
  for (PairGeometry& g : pairs_) {
    const SE3d T_th =
        map_->keyframe(cams_[g.target]).cam_from_world * map_->keyframe(cams_[g.host]).cam_from_world.Inverse();
    g.R = T_th.Rotation().cast<float>();
    g.t = T_th.Translation().cast<float>();
    g.A_host.setZero();
    g.A_host.topLeftCorner<6, 6>() = -T_th.Adj();
    g.A_host(6, 6) = g.A_host(7, 7) = 1.0;
    g.A_target.setZero();
    g.A_target.topLeftCorner<6, 6>().setIdentity();
    g.A_target(8, 6) = g.A_target(9, 7) = 1.0;
  }
}

// Fits the error models (pba_models.h) and stores the fitted ones in their keyframes.
void Problem::FitFromChunks(const std::vector<std::vector<std::vector<float>>>& chunk_residuals) {
  for (int c : FitPbaModels(chunk_residuals, cams_, fixed_, options_, &models_)) {
    Keyframe& k = map_->keyframe(cams_[c]);
    if (k.frozen) {
      models_[c] = k.error_model;
    } else {
      k.error_model = models_[c];
    }
  }
}

}  // namespace dsm::internal
