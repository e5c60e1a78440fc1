// SPDX-License-Identifier: MIT
#include "dsm/run/debug_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "dsm/io/image_io.h"
#include "dsm/mapping/projection.h"
#include "dsm/util/check.h"
#include "dsm/util/median.h"
#include "dsm/util/parse.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

double MedianOrNan(const std::vector<double>& v) { return v.empty() ? kNan : Median(v); }

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return kNan;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * v.size()));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

// The ground-truth camera centre at t_ns (a row within 1 ms), if any.
std::optional<Eigen::Vector3d> TrueCentre(const Trajectory& gt, int64_t t_ns) {
  const auto it = std::lower_bound(gt.stamps_ns.begin(), gt.stamps_ns.end(), t_ns - 1000000);
  if (it == gt.stamps_ns.end() || std::abs(*it - t_ns) > 1000000) return std::nullopt;
  return gt.poses[it - gt.stamps_ns.begin()].Translation();
}

// Jet colour map: t = 0 blue .. 1 red.
Rgb8 Jet(double t) {
  const auto c = [](double x) { return static_cast<uint8_t>(255.0 * std::clamp(1.5 - std::abs(x), 0.0, 1.0)); };
  t = std::clamp(t, 0.0, 1.0);
  return {c(4 * t - 3), c(4 * t - 2), c(4 * t - 1)};
}

std::string Number(double v) {
  if (!std::isfinite(v)) return "nan";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", v);
  return buffer;
}

// A CSV field in double quotes (a quote inside doubled).
std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

enum class InKeyframe { kNone, kGood, kOutlier };

struct PointRow {
  int id = -1;
  const Point* point = nullptr;
  Eigen::Vector3d world;
  bool in_view = false;
  Eigen::Vector2f px;  // In the keyframe.
  float idepth = 0.f;  // In the keyframe.
  InKeyframe state = InKeyframe::kNone;
  double true_host_depth = kNan;  // Rendered depth at the host pixel (metres).
  bool occluded = false;          // A nearer surface covers it in the keyframe (rendered depth).
};

}  // namespace

DebugWriter::DebugWriter(const fs::path& dir, const Dataset& dataset, const Undistorter& undistorter)
    : dir_(dir), dataset_(dataset), undistorter_(undistorter) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the debug folder (" + ec.message() + ")");
  table_.open(dir / "keyframes.csv");
  if (!table_) throw InputError((dir / "keyframes.csv").string() + ": cannot write file");
  table_ << "keyframe,frame,t_s,tracking_rmse,inlier_ratio,window,covisible,points,points_created,points_culled,"
            "observations_removed,reobservations,pba_iterations,step,median_depth,step_over_depth,gt_step_m,scale,"
            "scale_drift,depth_scale_drift,depth_bad_share,error_sigma,error_nu,inlier_threshold,"
            "observations_texture_lost\n";
  frames_.open(dir / "frames.csv");
  if (!frames_) throw InputError((dir / "frames.csv").string() + ": cannot write file");
  frames_ << "frame,map,status,keyframe,relocalised,tracking_ms,reason\n";
}

void DebugWriter::AddFrame(const FrameReport& report, int map) {
  WriteFrameRow(report.index, map, TrackingStatusName(report.status), report.keyframe, report.relocalised,
                report.tracking_ms, report.reason);
}

void DebugWriter::AddSkipped(int frame, int map, const std::string& error) {
  WriteFrameRow(frame, map, "skipped", false, false, kNan, error);
}

void DebugWriter::WriteFrameRow(int frame, int map, const std::string& status, bool keyframe, bool relocalised,
                                double tracking_ms, const std::string& reason) {
  frames_ << frame << ',' << map << ',' << status << ',' << keyframe << ',' << relocalised << ','
          << Number(tracking_ms) << ',' << Quoted(reason) << '\n';
  if (!frames_) throw InputError((dir_ / "frames.csv").string() + ": write failed");
}

void DebugWriter::AddKeyframes(const System& system) {
  // The first two keyframes are made together; both are described once the second is mapped.
  while (written_ < system.map().NumKeyframes() && written_ < static_cast<int>(system.stats().per_keyframe.size())) {
    WriteKeyframe(system, written_++);
  }
  table_.flush();
  if (!table_) throw InputError((dir_ / "keyframes.csv").string() + ": write failed");
}

const Image<float>* DebugWriter::Depth(int frame) {
  if (!dataset_.HasDepth()) return nullptr;
  auto it = depth_cache_.find(frame);
  if (it == depth_cache_.end()) {
    if (depth_cache_.size() > 32) depth_cache_.erase(depth_cache_.begin());  // The oldest frames.
    it = depth_cache_.emplace(frame, undistorter_.Apply(dataset_.LoadDepth(frame))).first;
  }
  return &it->second;
}

void DebugWriter::WriteKeyframe(const System& system, int kf) {
  const Map& map = system.map();
  const PinholeCamera& camera = undistorter_.output();
  const Keyframe& keyframe = map.keyframe(kf);
  const SystemStats::KeyframeLog& log = system.stats().per_keyframe[kf];
  const bool newest = kf == map.NumKeyframes() - 1;
  const std::vector<int> window = newest ? system.ActiveKeyframes() : std::vector<int>{kf};
  const std::vector<int> ids = newest ? system.ActivePointIds() : keyframe.points;

  // The points and where they are in this keyframe.
  std::vector<PointRow> rows;
  for (int pid : ids) {
    const Point& p = map.point(pid);
    if (p.removed) continue;
    PointRow row;
    row.id = pid;
    row.point = &p;
    row.world = PointInWorld(map, camera, p);
    row.in_view = p.host != kf && ProjectPoint(map, camera, p, kf, 0.f, &row.px, &row.idepth);
    for (const Observation& o : p.observations)
      if (o.target == kf) row.state = o.outlier ? InKeyframe::kOutlier : InKeyframe::kGood;
    if (const Image<float>* host_depth = Depth(map.keyframe(p.host).frame_index)) {
      const float d = Bilinear(*host_depth, p.pixel.x(), p.pixel.y());
      if (d > 0.f) row.true_host_depth = d;
    }
    rows.push_back(row);
  }

  // Motion against the map's depth, and against the ground truth.
  double step = kNan, gt_step = kNan, scale = kNan, drift = kNan;
  if (kf > 0) {
    const Keyframe& previous = map.keyframe(kf - 1);
    step = (keyframe.Centre() - previous.Centre()).norm();
    const auto c0 = TrueCentre(dataset_.ground_truth, previous.t_ns), c1 = TrueCentre(dataset_.ground_truth, keyframe.t_ns);
    if (c0 && c1) {
      gt_step = (*c1 - *c0).norm();
      if (gt_step > 1e-4) scale = step / gt_step;
      if (kf == 1 && std::isfinite(scale)) start_scale_ = scale;
      if (start_scale_) drift = scale / *start_scale_;
    }
  }
  std::vector<double> depths, idepths, ratios;
  for (const PointRow& r : rows) {
    if (!r.in_view) continue;
    depths.push_back(1.0 / r.idepth);
    idepths.push_back(r.idepth);
  }
  for (const PointRow& r : rows)
    if (std::isfinite(r.true_host_depth)) ratios.push_back(1.0 / r.point->idepth / r.true_host_depth);
  const double median_depth = MedianOrNan(depths);
  const double depth_scale = MedianOrNan(ratios);
  double depth_drift = kNan, bad_share = kNan;
  if (!ratios.empty()) {
    if (start_scale_) depth_drift = depth_scale / *start_scale_;
    int bad = 0;
    for (double q : ratios) bad += std::abs(q / depth_scale - 1.0) > 0.2;
    bad_share = static_cast<double>(bad) / ratios.size();
  }
  if (const Image<float>* depth = Depth(keyframe.frame_index); depth && std::isfinite(depth_scale)) {
    for (PointRow& r : rows) {
      if (!r.in_view || !depth->InBounds(r.px.x(), r.px.y())) continue;
      const float surface = Bilinear(*depth, r.px.x(), r.px.y());  // Metres.
      r.occluded = surface > 0.f && surface * depth_scale < 0.8 / r.idepth;
    }
  }

  table_ << kf << "," << keyframe.frame_index << "," << FormatSeconds(keyframe.t_ns) << ","
         << Number(log.tracking_rmse) << "," << Number(log.tracking_inlier_ratio) << "," << window.size() << ","
         << log.covisible.size() << "," << rows.size() << "," << log.points_created << "," << log.points_culled << ","
         << log.observations_removed << "," << log.reobservations << "," << log.pba_iterations << "," << Number(step)
         << "," << Number(median_depth) << "," << Number(step / median_depth) << "," << Number(gt_step) << ","
         << Number(scale) << "," << Number(drift) << "," << Number(depth_drift) << "," << Number(bad_share) << ","
         << Number(keyframe.error_model.sigma) << "," << Number(keyframe.error_model.nu) << ","
         << Number(keyframe.error_model.inlier_threshold) << ","
         << log.observations_texture_lost << "\n";

  char name[64];
  std::snprintf(name, sizeof(name), "kf_%05d_points.csv", kf);
  std::ofstream points(dir_ / name);
  points << "id,host,host_u,host_v,idepth,x,y,z,u,v,kf_idepth,good_observations,outlier_observations,in_keyframe,"
            "true_host_depth,occluded\n";
  static const char* kState[] = {"none", "good", "outlier"};
  for (const PointRow& r : rows) {
    const Point& p = *r.point;
    const int good = p.NumGoodObservations();
    points << r.id << "," << p.host << "," << Number(p.pixel.x()) << "," << Number(p.pixel.y()) << ","
           << Number(p.idepth) << "," << Number(r.world.x()) << "," << Number(r.world.y()) << ","
           << Number(r.world.z()) << "," << (r.in_view ? Number(r.px.x()) : "nan") << ","
           << (r.in_view ? Number(r.px.y()) : "nan") << "," << (r.in_view ? Number(r.idepth) : "nan") << "," << good
           << "," << p.observations.size() - good << "," << kState[static_cast<int>(r.state)] << ","
           << Number(r.true_host_depth) << "," << r.occluded << "\n";
  }
  if (!points) throw InputError((dir_ / name).string() + ": write failed");

  // The picture: the keyframe's image, its points by inverse depth and state.
  Image<Rgb8> picture(keyframe.width(), keyframe.height());
  for (int y = 0; y < picture.height(); ++y)
    for (int x = 0; x < picture.width(); ++x) {
      const auto v = static_cast<uint8_t>(std::clamp(keyframe.Intensity(x, y), 0.f, 255.f));
      picture(x, y) = {v, v, v};
    }
  const double lo = Quantile(idepths, 0.05), hi = Quantile(idepths, 0.95);
  const auto put = [&](int x, int y, Rgb8 c) {
    if (x >= 0 && y >= 0 && x < picture.width() && y < picture.height()) picture(x, y) = c;
  };
  for (const PointRow& r : rows) {
    if (!r.in_view) continue;
    const int x = static_cast<int>(std::lround(r.px.x())), y = static_cast<int>(std::lround(r.px.y()));
    const Rgb8 colour = Jet(hi > lo ? (r.idepth - lo) / (hi - lo) : 0.5);
    switch (r.state) {
      case InKeyframe::kNone: put(x, y, colour); break;
      case InKeyframe::kGood:
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) put(x + dx, y + dy, colour);
        break;
      case InKeyframe::kOutlier:
        for (int d = -2; d <= 2; ++d) put(x + d, y + d, {255, 0, 255}), put(x + d, y - d, {255, 0, 255});
        break;
    }
  }
  std::snprintf(name, sizeof(name), "kf_%05d.png", kf);
  WriteRgb8(dir_ / name, picture);
}

}  // namespace dsm
