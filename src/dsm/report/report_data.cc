// SPDX-License-Identifier: MIT
#include "dsm/report/report.h"

#include <fstream>

#include "dsm/io/ply.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string Base64(const void* data, size_t size) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const uint8_t*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (size_t i = 0; i < size; i += 3) {
    const uint32_t b0 = bytes[i], b1 = i + 1 < size ? bytes[i + 1] : 0, b2 = i + 2 < size ? bytes[i + 2] : 0;
    const uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < size ? kAlphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < size ? kAlphabet[triple & 63] : '=';
  }
  return out;
}

json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": missing (is this a dsm run's output folder?)");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(path.string() + ": not valid JSON (" + e.what() + ")");
  }
}

// A value of `j` at `key`, or `fallback` when absent or null.
template <typename T>
T Get(const json& j, const char* key, T fallback) {
  return j.contains(key) && !j[key].is_null() ? j[key].get<T>() : fallback;
}

// A trajectory the run wrote; one with no poses (the map never started, or an interrupted run) is
// empty, a missing one an InputError naming it.
Trajectory ReadRunTrajectory(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": missing (is this a dsm run's output folder?)");
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') return ReadTrajectory(path, TrajectoryFormat::kTum);
  }
  return {};
}

double Seconds(int64_t t_ns, int64_t t0_ns) { return 1e-9 * static_cast<double>(t_ns - t0_ns); }

// The points of a map's map.ply; `loaded_keyframes`: of a map loaded from a map file, its
// keyframes then (they come first), whose points the page draws apart from those the run added.
json PointsOf(const fs::path& ply, int loaded_keyframes) {
  std::vector<float> xyz;
  std::vector<uint8_t> grey;
  int loaded = 0;
  if (fs::exists(ply)) {
    const PlyCloud cloud = ReadPly(ply);
    const std::vector<int32_t>* host = nullptr;
    for (const auto& [name, values] : cloud.ints)
      if (name == "host") host = &values;
    for (size_t i = 0; i < cloud.xyz.size(); ++i) {
      xyz.insert(xyz.end(), cloud.xyz[i].data(), cloud.xyz[i].data() + 3);
      grey.push_back(cloud.rgb.empty() ? 200 : cloud.rgb[i][0]);
      loaded += host != nullptr && (*host)[i] < loaded_keyframes;
    }
  }
  json points = PointsJson(xyz, grey);
  // The map's points are in id order, so the loaded map's come first.
  points["loaded"] = loaded;
  return points;
}

// What the report reads of one map's folder.
struct MapFiles {
  Trajectory keyframes, frames;  // frames: empty when the file is missing.
  json eval;                     // eval.json, or null.
};

MapFiles ReadMapFiles(const fs::path& dir) {
  MapFiles f;
  f.keyframes = ReadRunTrajectory(dir / "keyframes.tum");
  if (fs::exists(dir / "frames.tum")) f.frames = ReadRunTrajectory(dir / "frames.tum");
  if (fs::exists(dir / "eval.json")) f.eval = ReadJson(dir / "eval.json");
  return f;
}

// One map's part of the document; `per_keyframe`: its keyframes' rows of stats.json.
// `loaded_keyframes`: the keyframes a loaded map had (its keyframes.tum holds those after them).
json MapOf(const fs::path& dir, const std::string& name, const MapFiles& files, const json& per_keyframe,
           int64_t t0_ns, json* errors, int map_index, int loaded_keyframes) {
  json m = {{"dir", name}, {"points", PointsOf(dir / "map.ply", loaded_keyframes)}};
  const Trajectory& keyframes = files.keyframes;
  json kfs = json::array(), links = json::array();
  for (size_t k = 0; k < keyframes.size(); ++k) {
    const json row = k < per_keyframe.size() ? per_keyframe[k] : json::object();
    const int id = loaded_keyframes + static_cast<int>(k);
    kfs.push_back(KeyframeJson(id, Get(row, "frame", -1), Seconds(keyframes.stamps_ns[k], t0_ns), keyframes.poses[k]));
    if (row.contains("covisible"))
      for (const json& c : row["covisible"]) links.push_back({id, c.get<int>()});
  }
  m["keyframes"] = kfs;
  m["covisibility"] = links;
  m["groundtruth"] = json::array();
  if (!fs::exists(dir / "groundtruth_in_map.tum") || files.frames.empty()) return m;
  const Trajectory gt = ReadRunTrajectory(dir / "groundtruth_in_map.tum");
  const Trajectory& frames = files.frames;
  for (size_t k = 0; k < gt.size(); ++k) {
    const Eigen::Vector3d p = gt.poses[k].Translation();
    m["groundtruth"].push_back({Seconds(gt.stamps_ns[k], t0_ns), p.x(), p.y(), p.z()});
  }
  // Errors: the frame and the ground-truth row of the same stamp, in the map's units times the
  // alignment's scale (metres per map unit).
  const double scale = files.eval.contains("frames") ? Get(files.eval["frames"], "scale", 1.0) : 1.0;
  json t = json::array(), error_mm = json::array();
  size_t g = 0;
  for (size_t f = 0; f < frames.size() && g < gt.size(); ++f) {
    while (g < gt.size() && gt.stamps_ns[g] < frames.stamps_ns[f]) ++g;
    if (g == gt.size() || gt.stamps_ns[g] != frames.stamps_ns[f]) continue;
    t.push_back(Seconds(frames.stamps_ns[f], t0_ns));
    error_mm.push_back(1000.0 * scale * (frames.poses[f].Translation() - gt.poses[g].Translation()).norm());
  }
  if (!t.empty()) errors->push_back({{"map", map_index}, {"t", t}, {"error_mm", error_mm}});
  return m;
}

}  // namespace

std::string ReportTitle(const fs::path& dataset) {
  return (dataset.filename().empty() ? dataset.parent_path() : dataset).filename().string();
}

json PointsJson(const std::vector<float>& xyz, const std::vector<uint8_t>& grey) {
  return {{"count", grey.size()}, {"xyz", Base64(xyz.data(), xyz.size() * sizeof(float))},
          {"grey", Base64(grey.data(), grey.size())}};
}

json KeyframeJson(int id, int frame, double t, const SE3d& world_from_cam) {
  const Eigen::Vector3d p = world_from_cam.Translation();
  const Eigen::Quaterniond q = world_from_cam.So3().Quaternion();
  return {{"id", id}, {"frame", frame}, {"t", t}, {"p", {p.x(), p.y(), p.z()}}, {"q", {q.x(), q.y(), q.z(), q.w()}}};
}

json ReportData(const fs::path& run_dir) {
  const json stats = ReadJson(run_dir / "stats.json");
  json data;
  const std::string dataset = Get(stats, "dataset", std::string());
  data["title"] = ReportTitle(dataset.empty() ? run_dir : fs::path(dataset));
  json summary;
  for (const char* key : {"frames", "frames_tracked", "keyframes", "map_points", "mode", "pace", "frames_per_second",
                          "realtime_factor", "frames_lost", "relocalisations", "interrupted", "map_loaded"})
    if (stats.contains(key)) summary[key] = stats[key];
  data["camera"] = Get(stats, "camera", json());
  data["per_frame"] = Get(stats, "per_frame", json{{"frame", json::array()}, {"tracking_ms", json::array()}});
  json per_keyframe = {{"frame", json::array()}, {"pba_ms", json::array()}, {"points_created", json::array()},
                       {"reobservations", json::array()}};
  const json rows = Get(stats, "per_keyframe", json::array());
  for (const json& row : rows) {
    per_keyframe["frame"].push_back(Get(row, "frame", -1));
    per_keyframe["pba_ms"].push_back(row.contains("pba") ? Get(row["pba"], "ms", 0.0) : 0.0);
    per_keyframe["points_created"].push_back(Get(row, "points_created", 0));
    per_keyframe["reobservations"].push_back(Get(row, "reobservations", 0));
  }
  data["per_keyframe"] = per_keyframe;
  data["lost_episodes"] = Get(stats, "lost_episodes", json::array());
  data["loops_closed"] = Get(stats, "loops_closed", json::array());
  data["maps_merged"] = Get(stats, "maps_merged", json::array());

  // The maps, each with its rows of per_keyframe (listed map after map).
  const json maps = Get(stats, "maps", json::array({{{"dir", "."}}}));
  data["maps"] = json::array();
  data["errors"] = json::array();
  int64_t t0_ns = 0;  // Times from the first map's first tracked frame (or keyframe).
  size_t row = 0;
  for (size_t k = 0; k < maps.size(); ++k) {
    const size_t n = Get(maps[k], "keyframes", rows.size());
    json slice = json::array();
    for (size_t i = row; i < std::min(rows.size(), row + n); ++i) slice.push_back(rows[i]);
    row += n;
    if (maps[k].contains("merged_into")) continue;  // Written with the map that took it in.
    const std::string name = maps[k].value("dir", ".");
    const MapFiles files = ReadMapFiles(run_dir / name);
    if (k == 0) {
      if (!files.frames.empty()) {
        t0_ns = files.frames.stamps_ns.front();
      } else if (!files.keyframes.empty()) {
        t0_ns = files.keyframes.stamps_ns.front();
      }
      if (files.eval.contains("keyframes")) {
        summary["keyframe_ate_mm"] = 1000.0 * files.eval["keyframes"]["ape"]["rmse"].get<double>();
      }
    }
    // A new map that never started while the camera went on in a loaded one (dsm run --load-map).
    if (n == 0 && !Get(maps[k], "loaded", false) && k > 0 && files.frames.empty()) continue;
    data["maps"].push_back(MapOf(run_dir / name, name, files, slice, t0_ns, &data["errors"], static_cast<int>(k),
                                 Get(maps[k], "keyframes_loaded", 0)));
  }
  data["summary"] = summary;
  return data;
}

}  // namespace dsm
