// SPDX-License-Identifier: MIT
#include "dsm/io/dataset.h"

#include <algorithm>
#include <sstream>

#include "dsm/io/image_io.h"
#include "dsm/util/check.h"
#include "dsm/util/parse.h"

namespace dsm {

namespace fs = std::filesystem;

bool Dataset::HasExposure() const {
  for (const auto& f : frames)
    if (f.exposure_ms > 0.0) return true;
  return false;
}

Image<uint8_t> Dataset::LoadImage(size_t i) const {
  DSM_CHECK(i < frames.size(), "frame index out of range");
  Image<uint8_t> image = images->Load(frames[i].image);
  if (image.width() != camera.width || image.height() != camera.height) {
    throw ImageSizeError(images->Describe() + "/" + frames[i].image + ": image is " + std::to_string(image.width()) +
                     "x" + std::to_string(image.height()) + " but the calibration says " +
                     std::to_string(camera.width) + "x" + std::to_string(camera.height));
  }
  return image;
}

void Dataset::PrefetchImage(size_t i) const {
  if (i < frames.size()) images->Prefetch(frames[i].image);
}

Image<float> Dataset::LoadDepth(size_t i) const {
  DSM_CHECK(i < frames.size(), "frame index out of range");
  if (!HasDepth()) throw InputError(root.string() + ": the dataset has no depth");
  const fs::path path = depth_dir / (fs::path(frames[i].image).stem().string() + ".tiff");
  std::error_code error;
  if (!fs::exists(path, error)) throw InputError(path.string() + ": depth file missing");
  Image<float> depth = ReadGrayFloat(path);
  if (depth.width() != camera.width || depth.height() != camera.height)
    throw InputError(path.string() + ": depth size differs from the calibration");
  return depth;
}

std::vector<FrameRecord> ReadTimesFile(const fs::path& times, const std::vector<std::string>& names,
                                       const TimesFormat& format) {
  std::vector<FrameRecord> frames;
  const size_t max_fields = std::max<size_t>(format.stamp_column + 1, format.exposure_column + 1);
  for (const DataRow& row : ReadDataRows(times, " \t,")) {
    const std::string where = Where(times, row.line);
    const auto& f = row.fields;
    if (f.size() <= format.stamp_column || f.size() > max_fields)
      throw InputError(where + ": expected '" + format.row_description + "'");
    if (frames.size() >= names.size()) throw InputError(where + ": more timestamps than images");
    double exposure = 0.0;
    if (format.exposure_column >= 0 && f.size() > static_cast<size_t>(format.exposure_column)) {
      exposure = ParseDouble(f[format.exposure_column], where);
      if (exposure < 0) throw InputError(where + ": negative exposure time");
    }
    frames.push_back({ParseTimestampNs(f[format.stamp_column], format.unit_ns, where), names[frames.size()], exposure});
  }
  if (frames.size() != names.size())
    throw InputError(times.string() + ": " + std::to_string(frames.size()) + " timestamps for " +
                     std::to_string(names.size()) + " images");
  ValidateFrames(frames, times.string());
  return frames;
}

void ValidateFrames(const std::vector<FrameRecord>& frames, const std::string& source) {
  if (frames.empty()) throw InputError(source + ": the dataset has no frames");
  for (size_t i = 1; i < frames.size(); ++i) {
    if (frames[i].t_ns <= frames[i - 1].t_ns) {
      throw InputError(source + ": timestamps must increase strictly (frame " + std::to_string(i) + ", " +
                       frames[i].image + ")");
    }
  }
}

std::string LineDelaySourceName(LineDelaySource source) {
  switch (source) {
    case LineDelaySource::kUnknown: return "unknown";
    case LineDelaySource::kCalibration: return "calibration";
    case LineDelaySource::kOption: return "option";
    case LineDelaySource::kEstimated: return "estimated";
  }
  return "?";
}

std::string GroundTruthConvention::Name() const {
  return std::string(frame == GtFrame::kBody ? "body" : "camera") +
         (quaternion == GtQuaternion::kHamilton ? "-hamilton" : "-jpl");
}

std::vector<GroundTruthConvention> AllGroundTruthConventions() {
  return {{GtFrame::kBody, GtQuaternion::kHamilton},
          {GtFrame::kBody, GtQuaternion::kJpl},
          {GtFrame::kCamera, GtQuaternion::kHamilton},
          {GtFrame::kCamera, GtQuaternion::kJpl}};
}

GtFrame ParseGtFrame(const std::string& name, const std::string& where) {
  if (name == "body") return GtFrame::kBody;
  if (name == "camera") return GtFrame::kCamera;
  throw InputError(where + ": expected body or camera, got '" + name + "'");
}

GtQuaternion ParseGtQuaternion(const std::string& name, const std::string& where) {
  if (name == "hamilton") return GtQuaternion::kHamilton;
  if (name == "jpl") return GtQuaternion::kJpl;
  throw InputError(where + ": expected hamilton or jpl, got '" + name + "'");
}

Dataset OpenDataset(const fs::path& path, const GroundTruthConvention& gt) {
  if (!fs::exists(path)) throw InputError(path.string() + ": dataset not found");
  if (fs::is_directory(path / "mav0" / "cam0")) return ReadEuroc(path / "mav0", gt);
  if (fs::is_directory(path / "cam0") && fs::exists(path / "cam0" / "data.csv")) return ReadEuroc(path, gt);
  if (!gt.IsDefault()) {
    throw InputError(path.string() + ": the ground-truth reading '" + gt.Name() +
                     "' applies to EuRoC datasets only (this one stores camera poses)");
  }
  if (fs::exists(path / "camera.txt") && fs::exists(path / "times.txt")) return ReadTumMono(path);
  if (fs::exists(path / "rgb.txt")) return ReadTumRgbd(path);
  if (fs::exists(path / "calib.txt") && fs::is_directory(path / "image_0")) return ReadKitti(path);
  if (fs::exists(path / "camera.yaml")) return ReadFolder(path);
  throw InputError(path.string() +
                   ": cannot detect the dataset format (expected EuRoC mav0/cam0, TUM monoVO camera.txt + "
                   "times.txt, TUM RGB-D rgb.txt, KITTI calib.txt + image_0/, or a folder with camera.yaml "
                   "and images/)");
}

std::string DescribeDataset(const Dataset& d) { return DescribeDataset(d, Undistorter(d.camera, {d.undistort_mode, 16})); }

std::string DescribeDataset(const Dataset& d, const Undistorter& und) {
  std::ostringstream out;
  out.precision(10);
  const CameraCalibration& c = d.camera;
  const double span_s = d.frames.size() > 1 ? (d.frames.back().t_ns - d.frames.front().t_ns) * 1e-9 : 0.0;
  out << "dataset:      " << d.root.string() << "\n"
      << "format:       " << d.format << "\n"
      << "frames:       " << d.frames.size() << "\n"
      << "resolution:   " << c.width << "x" << c.height << "\n"
      << "time span:    " << FormatSeconds(d.frames.front().t_ns) << " .. " << FormatSeconds(d.frames.back().t_ns)
      << " s (" << span_s << " s, " << (span_s > 0 ? (d.frames.size() - 1) / span_s : 0.0) << " Hz)\n"
      << "camera model: " << CameraModelName(c.model) << "\n"
      << "intrinsics:   fx " << c.fx << "  fy " << c.fy << "  cx " << c.cx << "  cy " << c.cy << "\n";
  if (!c.distortion.empty()) {
    out << "distortion:  ";
    for (double k : c.distortion) out << " " << k;
    out << "\n";
  }
  const PinholeCamera& p = und.output();
  out << "undistorted:  pinhole " << p.width << "x" << p.height << "  fx " << p.fx << "  fy " << p.fy << "  cx "
      << p.cx << "  cy " << p.cy << "  (" << (d.undistort_mode == UndistortMode::kCrop ? "crop" : "full")
      << ", " << 100.0 * und.ValidFraction() << "% valid)\n";
  out << "ground truth: ";
  if (d.HasGroundTruth()) {
    out << "yes (" << d.ground_truth.size() << " camera poses, " << d.ground_truth.PathLength() << " m path)\n";
  } else {
    out << "no\n";
  }
  out << "photometric:  ";
  if (d.photometric) {
    out << "yes (response " << (d.photometric->has_response() ? "yes" : "no") << ", vignette "
        << (d.photometric->has_vignette() ? "yes" : "no") << ")";
  } else {
    out << "no";
  }
  out << ", exposure times " << (d.HasExposure() ? "yes" : "no") << "\n";
  return out.str();
}

}  // namespace dsm
