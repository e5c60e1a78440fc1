// SPDX-License-Identifier: MIT
#include "dsm/io/calibration_io.h"

#include <fstream>
#include <set>

#include "dsm/io/image_io.h"
#include "dsm/io/yaml_file.h"
#include "dsm/util/check.h"
#include "dsm/util/parse.h"

namespace dsm {

namespace fs = std::filesystem;

CameraYaml ReadCameraYaml(const fs::path& path) {
  const YAML::Node node = LoadYamlMapping(path);
  static const std::set<std::string> kKeys{"model", "width", "height", "intrinsics", "distortion", "rate_hz", "line_delay_us"};
  for (const auto& kv : node) {
    const std::string key = KeyName(kv.first, path);
    if (!kKeys.count(key)) throw InputError(path.string() + ": unknown key '" + key + "'");
  }
  CameraYaml out;
  CameraCalibration& cam = out.camera;
  cam.model = ParseCameraModel(Get<std::string>(node, "model", path), path.string() + ": key 'model'");
  cam.width = Get<int>(node, "width", path);
  cam.height = Get<int>(node, "height", path);
  const auto k = Get<std::vector<double>>(node, "intrinsics", path);
  if (k.size() != 4) throw InputError(path.string() + ": key 'intrinsics' needs 4 values [fx, fy, cx, cy]");
  cam.fx = k[0], cam.fy = k[1], cam.cx = k[2], cam.cy = k[3];
  if (node["distortion"]) cam.distortion = Get<std::vector<double>>(node, "distortion", path);
  if (node["rate_hz"]) {
    out.rate_hz = Get<double>(node, "rate_hz", path);
    if (!(out.rate_hz > 0)) throw InputError(path.string() + ": key 'rate_hz' must be positive");
  }
  if (node["line_delay_us"]) {
    out.line_delay_us = Get<double>(node, "line_delay_us", path);
    if (!ReadoutFits(*out.line_delay_us, cam.height, 1e6 / out.rate_hz))
      throw InputError(path.string() + ": key 'line_delay_us' must be within 0 and the frame interval over the rows");
  }
  cam.Validate(path.string());
  return out;
}

void WriteCameraYaml(const fs::path& path, const CameraYaml& c) {
  std::ofstream out(path);
  if (!out) throw InputError(path.string() + ": cannot write file");
  out.precision(17);
  out << "model: " << CameraModelName(c.camera.model) << "\nwidth: " << c.camera.width
      << "\nheight: " << c.camera.height << "\nintrinsics: [" << c.camera.fx << ", " << c.camera.fy << ", "
      << c.camera.cx << ", " << c.camera.cy << "]\ndistortion: [";
  for (size_t i = 0; i < c.camera.distortion.size(); ++i) out << (i ? ", " : "") << c.camera.distortion[i];
  out << "]\nrate_hz: " << c.rate_hz << "\n";
  if (c.line_delay_us) out << "line_delay_us: " << *c.line_delay_us << "\n";
  if (!out) throw InputError(path.string() + ": write failed");
}

EurocSensor ReadEurocSensorYaml(const fs::path& path) {
  const YAML::Node node = LoadYamlMapping(path);
  EurocSensor out;
  CameraCalibration& cam = out.camera;
  const auto k = Get<std::vector<double>>(node, "intrinsics", path);
  if (k.size() != 4) throw InputError(path.string() + ": key 'intrinsics' needs 4 values");
  cam.fx = k[0], cam.fy = k[1], cam.cx = k[2], cam.cy = k[3];
  const auto res = Get<std::vector<int>>(node, "resolution", path);
  if (res.size() != 2) throw InputError(path.string() + ": key 'resolution' needs 2 values");
  cam.width = res[0], cam.height = res[1];
  const std::string model = Get<std::string>(node, "camera_model", path);
  if (model != "pinhole") throw InputError(path.string() + ": camera_model '" + model + "' is not supported (pinhole)");
  const std::string dist = node["distortion_model"] ? Get<std::string>(node, "distortion_model", path) : "none";
  cam.model = ParseCameraModel(dist, path.string() + ": key 'distortion_model'");
  if (node["distortion_coefficients"]) cam.distortion = Get<std::vector<double>>(node, "distortion_coefficients", path);
  cam.Validate(path.string());
  if (node["rate_hz"]) out.rate_hz = Get<double>(node, "rate_hz", path);
  if (!node["T_BS"] || !node["T_BS"].IsMap()) throw InputError(path.string() + ": missing key 'T_BS'");
  const auto t = Get<std::vector<double>>(node["T_BS"], "data", path);
  if (t.size() != 16) throw InputError(path.string() + ": key 'T_BS.data' needs 16 values");
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = t[i];
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-4 || R.determinant() < 0)
    throw InputError(path.string() + ": T_BS is not a rigid transform");
  out.body_from_cam = SE3d(m);
  return out;
}

TumMonoCamera ReadTumMonoCamera(const fs::path& path) {
  const auto lines = ReadLines(path);
  if (lines.size() < 2) throw InputError(path.string() + ": expected at least 2 lines (model, size)");
  TumMonoCamera out;
  CameraCalibration& cam = out.camera;
  auto f = SplitFields(lines[0], " \t");
  const std::string where0 = Where(path, 0);
  if (!f.empty() && std::isalpha(static_cast<unsigned char>(f[0][0]))) {
    std::string name = f[0];
    f.erase(f.begin());
    if (name == "RadTan") name = "radtan";
    if (name == "EquiDistant" || name == "KannalaBrandt") name = "equidistant";
    cam.model = ParseCameraModel(name, where0);
  } else {
    cam.model = CameraModel::kFov;
  }
  if (f.size() < 4) throw InputError(where0 + ": expected fx fy cx cy and the model parameters");
  std::vector<double> v;
  for (const auto& s : f) v.push_back(ParseDouble(s, where0));
  const auto size = SplitFields(lines[1], " \t");
  if (size.size() != 2) throw InputError(Where(path, 1) + ": expected 'width height'");
  cam.width = static_cast<int>(ParseInt(size[0], Where(path, 1)));
  cam.height = static_cast<int>(ParseInt(size[1], Where(path, 1)));
  cam.fx = v[0], cam.fy = v[1], cam.cx = v[2], cam.cy = v[3];
  if (cam.fx < 1 && cam.fy < 1) {
    // Relative intrinsics; the 0.5 moves the principal point to our pixel-centre convention.
    cam.fx *= cam.width;
    cam.fy *= cam.height;
    cam.cx = cam.cx * cam.width - 0.5;
    cam.cy = cam.cy * cam.height - 0.5;
  }
  cam.distortion.assign(v.begin() + 4, v.end());
  if (cam.model == CameraModel::kPinhole) {
    // "Pinhole fx fy cx cy 0": a trailing zero is allowed.
    for (double d : cam.distortion)
      if (d != 0.0) throw InputError(where0 + ": a pinhole camera takes no distortion");
    cam.distortion.clear();
  }
  cam.Validate(path.string());
  if (lines.size() >= 3) {
    const std::string mode(Trim(lines[2]));
    if (mode == "full") out.mode = UndistortMode::kFull;
    // "crop", "none" and explicit output cameras use the all-valid crop.
  }
  return out;
}

CameraCalibration ReadKittiCalib(const fs::path& path, int width, int height) {
  const auto lines = ReadLines(path);
  for (size_t i = 0; i < lines.size(); ++i) {
    auto f = SplitFields(lines[i], " \t");
    if (f.empty() || f[0] != "P0:") continue;
    if (f.size() != 13) throw InputError(Where(path, i) + ": P0 needs 12 values");
    CameraCalibration cam;
    cam.model = CameraModel::kPinhole;
    cam.width = width;
    cam.height = height;
    cam.fx = ParseDouble(f[1], Where(path, i));
    cam.cx = ParseDouble(f[3], Where(path, i));
    cam.fy = ParseDouble(f[6], Where(path, i));
    cam.cy = ParseDouble(f[7], Where(path, i));
    cam.Validate(path.string());
    return cam;
  }
  throw InputError(path.string() + ": no 'P0:' line");
}

std::optional<PhotometricCalibration> ReadPhotometricCalibration(const fs::path& folder) {
  const fs::path pcalib = folder / "pcalib.txt";
  const fs::path vignette = folder / "vignette.png";
  if (!fs::exists(pcalib) && !fs::exists(vignette)) return std::nullopt;
  PhotometricCalibration calib;
  if (fs::exists(pcalib)) {
    std::vector<double> values;
    const auto lines = ReadLines(pcalib);
    for (size_t i = 0; i < lines.size(); ++i)
      for (const auto& s : SplitFields(lines[i], " \t")) values.push_back(ParseDouble(s, Where(pcalib, i)));
    if (values.size() != 256)
      throw InputError(pcalib.string() + ": expected 256 inverse-response values, found " + std::to_string(values.size()));
    std::array<double, 256> g;
    std::copy(values.begin(), values.end(), g.begin());
    calib.SetInverseResponse(g, pcalib.string());
  }
  if (fs::exists(vignette)) calib.SetVignette(ReadGrayFloat(vignette), vignette.string());
  return calib;
}

}  // namespace dsm
