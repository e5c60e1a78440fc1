// SPDX-License-Identifier: MIT
// Python bindings (pybind11): `import dsm`.
//   dsm.run(dataset, out="dsm_out", **options) -> dict        as `dsm run`; returns stats.json
//   dsm.read_dataset(path, topic=None, ...) -> Dataset         frames ready for System.process
// A dataset is a folder or a recording (a .bag: `topic`, `calib`, `gt_topic`, `gt_frames` as
// dsm run's --topic, --calib, --gt-topic, --gt-frames).
//   dsm.System(camera, options=None, map=None, localize=False) the system facade, sequential, with
//       its maps as `dsm run` has them (system/atlas.h): .process(t_ns, image) -> dict, .finish(),
//       .keyframe_trajectory(map=0), .frame_trajectory(map=0), .map_points(map=0), .save_map(path)
// Trajectories are (N, 8) float64 arrays of t (seconds) x y z qx qy qz qw (world_from_cam); map
// points (N, 3) float64. Bad input raises dsm.InputError (a ValueError) with dsm's message.
#include <map>
#include <optional>
#include <tuple>
#include <utility>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <nlohmann/json.hpp>

#include "dsm/bag/bag_dataset.h"
#include "dsm/geometry/undistorter.h"
#include "dsm/io/dataset.h"
#include "dsm/config/option_registry.h"
#include "dsm/mapfile/map_file.h"
#include "dsm/mapping/map_points.h"
#include "dsm/run/frame_reader.h"
#include "dsm/run/run.h"
#include "dsm/system/atlas.h"
#include "dsm/system/system.h"
#include "dsm/util/check.h"
#include "dsm/util/version.h"

namespace py = pybind11;

namespace dsm {
namespace {

// Python values as JSON text (json.dumps), which dsm's option parser reads as YAML.
std::string ToJsonText(const py::object& value) {
  return py::module_::import("json").attr("dumps")(value).cast<std::string>();
}

py::object FromJson(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

SystemOptions OptionsFrom(const py::object& options) {
  SystemOptions o;
  if (!options.is_none()) ApplyOptionsText(ToJsonText(options), "options", &o);
  return o;
}

py::array_t<double> TrajectoryArray(const Trajectory& t) {
  py::array_t<double> out({static_cast<py::ssize_t>(t.size()), py::ssize_t{8}});
  auto a = out.mutable_unchecked<2>();
  for (size_t i = 0; i < t.size(); ++i) {
    const Eigen::Vector3d p = t.poses[i].Translation();
    const Eigen::Quaterniond q = t.poses[i].So3().Quaternion();
    const double row[8] = {1e-9 * static_cast<double>(t.stamps_ns[i]), p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()};
    for (int k = 0; k < 8; ++k) a(i, k) = row[k];
  }
  return out;
}

py::dict CameraDict(const PinholeCamera& c) {
  py::dict d;
  d["width"] = c.width;
  d["height"] = c.height;
  d["fx"] = c.fx;
  d["fy"] = c.fy;
  d["cx"] = c.cx;
  d["cy"] = c.cy;
  return d;
}

PinholeCamera CameraFrom(const py::dict& d) {
  PinholeCamera c;
  try {
    c.width = d["width"].cast<int>();
    c.height = d["height"].cast<int>();
    c.fx = d["fx"].cast<double>();
    c.fy = d["fy"].cast<double>();
    c.cx = d["cx"].cast<double>();
    c.cy = d["cy"].cast<double>();
  } catch (const py::error_already_set&) {
    throw InputError("camera: expected a dict with width, height, fx, fy, cx, cy");
  } catch (const py::cast_error&) {
    throw InputError("camera: width, height must be integers and fx, fy, cx, cy numbers");
  }
  if (c.width < 16 || c.height < 16 || !(c.fx > 0) || !(c.fy > 0)) throw InputError("camera: implausible values");
  return c;
}

py::array_t<float> ImageArray(const Image<float>& image) {
  py::array_t<float> out({static_cast<py::ssize_t>(image.height()), static_cast<py::ssize_t>(image.width())});
  auto a = out.mutable_unchecked<2>();
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) a(y, x) = image(x, y);
  return out;
}

// A dataset with its undistorter: frame i as System.process takes it.
// What a recording needs besides its path (bag/bag_dataset.h); empty for a folder.
struct RecordingArgs {
  std::optional<std::string> topic, calib, gt_topic;
  std::optional<std::pair<std::string, std::string>> gt_frames;
  bool Any() const { return topic || calib || gt_topic || gt_frames; }
};

Dataset OpenPath(const std::string& path, const RecordingArgs& recording) {
  if (!IsBagPath(path)) {
    if (recording.Any()) throw InputError(path + ": topic, calib, gt_topic and gt_frames are for recordings (.bag)");
    return OpenDataset(path);
  }
  BagInput input;
  input.topic = recording.topic.value_or("");
  input.calib = recording.calib.value_or("");
  input.gt_topic = recording.gt_topic.value_or("");
  if (recording.gt_frames) std::tie(input.gt_parent, input.gt_child) = *recording.gt_frames;
  return OpenBag(path, input);
}

struct PyDataset {
  PyDataset(const std::string& path, const RecordingArgs& recording)
      : dataset(OpenPath(path, recording)),
        undistorter(FrameUndistorter(dataset, SystemOptions{})) {}
  Dataset dataset;
  Undistorter undistorter;
};

struct PyFrame {
  int index = -1;
  int64_t t_ns = 0;
  double exposure_ms = 0.0;
  py::object image;  // float32 (height, width), or None when the file could not be used ...
  std::string error; // ... and why.
};

// A map file read whole (mapfile/map_file.h): what it holds, and where it came from (a System
// given it reads its first map from there again).
struct PyMap {
  std::string path;
  MapFile file;

  int Keyframes() const {
    int n = 0;
    for (const StoredMap& m : file.maps) n += m.map.NumKeyframes();
    return n;
  }
  int Points() const {
    int n = 0;
    for (const StoredMap& m : file.maps) n += m.map.NumLivePoints();
    return n;
  }
};

// The system facade, one thread (each keyframe mapped before process returns: deterministic), over
// an Atlas (system/atlas.h) as `dsm run` is: after a loss that relocalisation cannot end a new map
// starts, the camera returns into a map it left, and a map that recognises another takes it in.
class PySystem {
 public:
  PySystem(const py::dict& camera, const py::object& options, const py::object& map, bool localize)
      : camera_(CameraFrom(camera)), options_(OptionsFrom(options)) {
    options_yaml_ = OptionsYaml(options_);
    std::vector<StoredMap> loaded;
    if (map.is_none()) {
      if (localize) throw InputError("System: localize needs a map to localise in (map=load_map(...))");
    } else {
      const PyMap& m = map.cast<const PyMap&>();
      // Localising, the maps saved are the loaded ones, as the options of their own run made them.
      if (localize) options_yaml_ = m.file.options;
      loaded = MapsToTakeUp(m.path, ReadMapFile(m.path), camera_);
    }
    atlas_.emplace([this] { return std::make_unique<System>(camera_, options_); },
                   [this](int id, System& system, const Atlas::Spans&, int merged_into) {
                     EndMap(id, system, merged_into);
                   },
                   std::move(loaded), localize ? System::LoadedMapUse::kLocalize : System::LoadedMapUse::kExtend);
  }

  // Writes the maps to a map file; the system is done then (its maps are handed over).
  void SaveMap(const std::string& path) {
    CheckOpen();
    MapFile file;
    file.created_by = std::string("dsm ") + kVersion;
    file.camera = camera_;
    file.options = options_yaml_;
    {
      py::gil_scoped_release release;
      saving_ = true;
      Close();
    }
    for (auto& [id, stored] : stored_)
      if (stored.map.NumKeyframes() > 0) file.maps.push_back(std::move(stored));
    WriteMapFile(path, file);
  }

  py::dict Process(int64_t t_ns, const py::array_t<float, py::array::c_style | py::array::forcecast>& image,
                   double exposure_ms) {
    CheckOpen();
    if (image.ndim() != 2 || image.shape(0) != camera_.height || image.shape(1) != camera_.width) {
      throw InputError("process: image must be a (" + std::to_string(camera_.height) + ", " +
                       std::to_string(camera_.width) + ") array of grey values");
    }
    Image<float> frame(camera_.width, camera_.height);
    auto a = image.unchecked<2>();
    for (int y = 0; y < camera_.height; ++y)
      for (int x = 0; x < camera_.width; ++x) frame(x, y) = a(y, x);
    const int index = next_index_;
    std::vector<Atlas::Settled> settled;
    {
      py::gil_scoped_release release;
      settled = atlas_->Process(index, t_ns, frame, exposure_ms, std::nullopt);
      ++next_index_;
      // Relocalisation keeps failing: the camera is somewhere new, and another map starts.
      if (atlas_->current().NeedsNewMap()) atlas_->StartNewMap();
    }
    py::dict d;
    d["index"] = index;
    // Pending: it waits for the next frame to confirm a relocalisation in another map.
    d["status"] = "pending";
    d["keyframe"] = false;
    d["relocalised"] = false;
    d["reason"] = "";
    d["tracking_ms"] = 0.0;
    d["map"] = -1;
    for (const Atlas::Settled& st : settled) {
      if (st.report.index != index) continue;
      const FrameReport& r = st.report;
      d["status"] = TrackingStatusName(r.status);
      d["keyframe"] = r.keyframe;
      d["relocalised"] = r.relocalised || r.resumed;
      d["reason"] = r.reason;
      d["tracking_ms"] = r.tracking_ms;
      d["map"] = st.map;
    }
    return d;
  }

  void Finish() {
    CheckOpen();
    py::gil_scoped_release release;
    atlas_->Flush();
    atlas_->current().Finish();
  }
  py::array_t<double> KeyframeTrajectory(int map) const {
    const System* s = Held(map);
    return TrajectoryArray(s ? s->KeyframeTrajectory() : Ended(map).keyframes);
  }
  py::array_t<double> FrameTrajectory(int map) const {
    const System* s = Held(map);
    return TrajectoryArray(s ? s->FrameTrajectory() : Ended(map).frames);
  }
  py::array_t<double> MapPoints(int map) const {
    const System* s = Held(map);
    const std::vector<Eigen::Vector3d> points = s ? WorldPoints(*s, camera_) : Ended(map).points;
    py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
    auto a = out.mutable_unchecked<2>();
    for (size_t i = 0; i < points.size(); ++i)
      for (int k = 0; k < 3; ++k) a(i, k) = points[i][k];
    return out;
  }

 private:
  // A map's trajectories and points, as it is now or as it ended.
  struct MapOutputs {
    Trajectory keyframes, frames;
    std::vector<Eigen::Vector3d> points;
  };

  static std::vector<Eigen::Vector3d> WorldPoints(const System& system, const PinholeCamera& camera) {
    std::vector<Eigen::Vector3d> points;
    for (const LivePoint& p : LivePoints(system.map(), camera)) points.push_back(p.world.cast<double>());
    return points;
  }

  void EndMap(int id, System& system, int merged_into) {
    if (merged_into >= 0) return;  // Its keyframes and frames are the other map's now.
    system.Finish();
    // A map saved is adjusted whole first (System::TakeStoredMap): its outputs are the map's as saved.
    const bool saved = saving_ && atlas_->SavedInMapFile(system);
    if (saved && !system.localizing()) system.RunGlobalBundleAdjustment();
    ended_[id] = {system.KeyframeTrajectory(), system.FrameTrajectory(), WorldPoints(system, camera_)};
    if (saved) stored_.emplace(id, system.TakeStoredMap());
  }

  // Map `map` while the atlas holds it (0: the first map, which keeps the whole trajectory after
  // merges, as `dsm run` writes it to its output folder); null once it ended.
  const System* Held(int map) const { return closed_ ? nullptr : atlas_->Find(map); }
  // The outputs of map `map` as it ended.
  const MapOutputs& Ended(int map) const {
    const auto it = ended_.find(map);
    if (it == ended_.end()) throw InputError("System: no map " + std::to_string(map));
    return it->second;
  }

  void Close() {
    atlas_->Close();
    closed_ = true;
  }

  void CheckOpen() const {
    if (closed_) throw InputError("the system's map was saved (save_map): it takes no more frames");
  }

  PinholeCamera camera_;
  SystemOptions options_;
  std::string options_yaml_;  // The map file's options (MapFile::options).
  std::optional<Atlas> atlas_;
  std::map<int, MapOutputs> ended_;  // By map id: maps the atlas ended.
  std::map<int, StoredMap> stored_;  // By map id: the maps ended for the map file (saving_).
  bool saving_ = false;  // Maps ended from now on are stored for the map file.
  int next_index_ = 0;
  bool closed_ = false;
};

py::dict Run(const std::string& dataset_path, const std::string& out, const std::string& mode, const std::string& pace,
             int start, int end, bool global_ba, bool write_map, bool write_report, const py::object& options,
             bool quiet, const std::string& load_map, const std::string& save_map, bool localize,
             const std::string& mcap, const RecordingArgs& recording) {
  RunOptions o;
  o.system = OptionsFrom(options);
  o.system.mode = ParseMapMode(mode, "mode");
  o.pace = ParsePace(pace, "pace");
  o.start = start;
  o.end = end;
  o.global_ba = global_ba;
  o.write_map = write_map;
  o.write_report = write_report;
  o.quiet = quiet;
  o.load_map = load_map;
  o.save_map = save_map;
  o.mcap = mcap;
  o.localize = localize;
  const Dataset dataset = OpenPath(dataset_path, recording);
  RunSummary summary;
  {
    py::gil_scoped_release release;
    summary = RunDataset(dataset, o, out);
  }
  py::dict stats = FromJson(summary.stats);
  if (summary.eval) stats["eval"] = FromJson(*summary.eval);
  return stats;
}

}  // namespace
}  // namespace dsm

PYBIND11_MODULE(dsm, m) {
  using namespace dsm;
  m.doc() = "dsm: monocular visual SLAM by Direct Sparse Mapping";
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);

  m.def("run",
        [](const std::string& dataset, const std::string& out, const std::string& mode, const std::string& pace,
           int start, int end, bool global_ba, bool write_map, bool write_report, const py::object& options,
           bool quiet, const std::string& load_map, const std::string& save_map, bool localize,
           const std::string& mcap, std::optional<std::string> topic, std::optional<std::string> calib, std::optional<std::string> gt_topic,
           std::optional<std::pair<std::string, std::string>> gt_frames) {
          return Run(dataset, out, mode, pace, start, end, global_ba, write_map, write_report, options, quiet,
                     load_map, save_map, localize, mcap, {topic, calib, gt_topic, gt_frames});
        },
        py::arg("dataset"), py::kw_only(), py::arg("out") = "dsm_out", py::arg("mode") = "dsm",
        py::arg("pace") = "sequential", py::arg("start") = 0, py::arg("end") = -1, py::arg("global_ba") = false,
        py::arg("write_map") = true, py::arg("write_report") = true, py::arg("options") = py::none(),
        py::arg("quiet") = true, py::arg("load_map") = "", py::arg("save_map") = "", py::arg("localize") = false,
        py::arg("mcap") = "", py::arg("topic") = py::none(), py::arg("calib") = py::none(), py::arg("gt_topic") = py::none(),
        py::arg("gt_frames") = py::none(),
        "Runs SLAM over a dataset folder or a recording (.bag) as `dsm run` does (default pace: sequential, deterministic) and "
        "returns stats.json as a dict (with 'eval' when the dataset has ground truth). `options`: a dict of option "
        "sections, as in a --config file, e.g. {'window': {'temporal_keyframes': 5}}. `load_map`, `save_map`, "
        "`localize`, `mcap`: as --load-map, --save-map, --localize and --mcap. `topic`, `calib`, `gt_topic`, `gt_frames` (a pair of "
        "frame names): a recording's, as --topic, --calib, --gt-topic and --gt-frames.");

  py::class_<PyFrame>(m, "Frame")
      .def_readonly("index", &PyFrame::index)
      .def_readonly("t_ns", &PyFrame::t_ns)
      .def_readonly("exposure_ms", &PyFrame::exposure_ms)
      .def_readonly("image", &PyFrame::image)
      .def_readonly("error", &PyFrame::error);

  py::class_<PyDataset>(m, "Dataset")
      .def("__len__", [](const PyDataset& d) { return d.dataset.size(); })
      .def("__getitem__",
           [](const PyDataset& d, py::ssize_t i) {
             const auto n = static_cast<py::ssize_t>(d.dataset.size());
             if (i < 0) i += n;
             if (i < 0 || i >= n) throw py::index_error("frame index out of range");
             FrameOrError f;
             {
               py::gil_scoped_release release;
               f = TryReadFrame(d.dataset, d.undistorter, static_cast<int>(i));
             }
             PyFrame frame;
             frame.index = static_cast<int>(i);
             frame.t_ns = d.dataset.frames[i].t_ns;
             frame.exposure_ms = d.dataset.frames[i].exposure_ms;
             frame.image = f.error.empty() ? py::object(ImageArray(f.image)) : py::none();
             frame.error = f.error;
             return frame;
           })
      .def_property_readonly("camera", [](const PyDataset& d) { return CameraDict(d.undistorter.output()); },
                             "The undistorted pinhole camera the frames are in (System's camera)")
      .def_property_readonly("format", [](const PyDataset& d) { return d.dataset.format; })
      .def_property_readonly("ground_truth", [](const PyDataset& d) { return TrajectoryArray(d.dataset.ground_truth); });
  m.def("read_dataset",
        [](const std::string& path, std::optional<std::string> topic, std::optional<std::string> calib,
           std::optional<std::string> gt_topic, std::optional<std::pair<std::string, std::string>> gt_frames) {
          return std::make_unique<PyDataset>(path, RecordingArgs{topic, calib, gt_topic, gt_frames});
        },
        py::arg("path"), py::arg("topic") = py::none(), py::kw_only(), py::arg("calib") = py::none(),
        py::arg("gt_topic") = py::none(), py::arg("gt_frames") = py::none(),
        "Opens a dataset folder (EuRoC, TUM, KITTI, generic) or a recording (.bag; `topic`, `calib`, `gt_topic`, "
        "`gt_frames` as dsm run's --topic, --calib, --gt-topic, --gt-frames). Indexing or iterating gives Frame objects whose image is "
        "undistorted and photometrically corrected (float32), ready for System.process.");

  py::class_<PyMap>(m, "Map")
      .def_readonly("path", &PyMap::path)
      .def_property_readonly("maps", [](const PyMap& p) { return p.file.maps.size(); })
      .def_property_readonly("keyframes", &PyMap::Keyframes)
      .def_property_readonly("points", &PyMap::Points, "Live points")
      .def_property_readonly("camera", [](const PyMap& p) { return CameraDict(p.file.camera); })
      .def_property_readonly("created_by", [](const PyMap& p) { return p.file.created_by; })
      .def("save", [](const PyMap& p, const std::string& path) { WriteMapFile(path, p.file); }, py::arg("path"),
           "Writes the map file again (the same bytes as the file read)")
      .def("__str__", [](const PyMap& p) { return DescribeMapFile(p.path, p.file); });
  m.def("load_map", [](const std::string& path) { return std::make_unique<PyMap>(PyMap{path, ReadMapFile(path)}); },
        py::arg("path"),
        "Reads a map file (dsm run --save-map, System.save_map) whole; InputError naming it when it is not a valid "
        "one");

  py::class_<PySystem>(m, "System")
      .def(py::init<const py::dict&, const py::object&, const py::object&, bool>(), py::arg("camera"),
           py::arg("options") = py::none(), py::arg("map") = py::none(), py::arg("localize") = false,
           "camera: dict width, height, fx, fy, cx, cy (an undistorted pinhole camera, e.g. Dataset.camera); "
           "options: dict of option sections; map: a Map (load_map) whose maps the system relocalises in (three "
           "frames that agree, a fourth that confirms) and goes on in their frame and scale, extending them, or "
           "with localize=True leaving them unchanged (its keyframes are then temporary, and save_map writes the "
           "maps as they were loaded). After a loss that relocalisation cannot end a new map starts, and maps "
           "are merged when one recognises another, as in `dsm run`.")
      .def("save_map", &PySystem::SaveMap, py::arg("path"),
           "Writes the system's maps to a map file (after all their mapping); the system takes no frames after")
      .def("process", &PySystem::Process, py::arg("t_ns"), py::arg("image"), py::arg("exposure_ms") = 0.0,
           "Tracks (and maps) one frame: image (height, width), grey values; returns its index, status (initializing, "
           "ok, lost, or pending while it waits for the next frame to confirm a relocalisation in another map), "
           "keyframe, relocalised, reason and the map that took it")
      .def("finish", &PySystem::Finish, "Waits for all mapping, and takes a frame still pending")
      .def("keyframe_trajectory", &PySystem::KeyframeTrajectory, py::arg("map") = 0,
           "world_from_cam of the keyframes of map `map` (0: the first, which takes in the maps it merges)")
      .def("frame_trajectory", &PySystem::FrameTrajectory, py::arg("map") = 0)
      .def("map_points", &PySystem::MapPoints, py::arg("map") = 0);
}
