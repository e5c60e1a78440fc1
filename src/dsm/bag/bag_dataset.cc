// SPDX-License-Identifier: MIT
#include "dsm/bag/bag_dataset.h"

#include <algorithm>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>

#include "dsm/bag/bag_ground_truth.h"
#include "dsm/bag/image_message.h"
#include "dsm/bag/messages.h"
#include "dsm/io/calibration_io.h"
#include "dsm/io/yaml_file.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

bool IsImageType(const std::string& type) {
  return type == "sensor_msgs/Image" || type == "sensor_msgs/CompressedImage";
}

std::string ListTopics(const std::vector<BagTopic>& topics) {
  std::string names;
  for (const BagTopic& t : topics) names += (names.empty() ? "" : ", ") + t.name;
  return names;
}

// One image message decoded: its header stamp and, when asked, its pixels.
struct DecodedFrame {
  int64_t stamp_ns = 0;
  Image<uint8_t> image;
};

DecodedFrame DecodeFrame(const BagFile& bag, const std::string& topic, bool compressed, size_t index, bool pixels) {
  const std::string where = bag.path().string() + " " + topic + " message " + std::to_string(index);
  const std::vector<uint8_t> bytes = bag.Read(topic, index);
  WireReader in(bytes.data(), bytes.size(), bag.WireOf(topic), where);
  DecodedFrame frame;
  if (compressed) {
    const CompressedImageMessage m = DecodeCompressedImage(in);
    frame.stamp_ns = m.stamp_ns;
    if (pixels) frame.image = CompressedImageToGray8(m, where);
  } else {
    const ImageMessage m = DecodeImage(in);
    frame.stamp_ns = m.stamp_ns;
    if (pixels) frame.image = ImageMessageToGray8(m, where);
  }
  return frame;
}

// The image topic's messages, named by their index ("0", "1", ...), read as they are loaded.
class BagImageStore : public ImageStore {
 public:
  BagImageStore(std::shared_ptr<const BagFile> bag, std::string topic, bool compressed, size_t count)
      : bag_(std::move(bag)), topic_(std::move(topic)), compressed_(compressed), count_(count) {}

  Image<uint8_t> Load(const std::string& name) const override {
    size_t index = 0;
    const bool digits = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!digits || name.size() > 18 || (index = std::stoull(name)) >= count_) {
      throw InputError(bag_->path().string() + " " + topic_ + ": no message " + name);
    }
    return DecodeFrame(*bag_, topic_, compressed_, index, true).image;
  }

  std::vector<std::string> List() const override {
    std::vector<std::string> names;
    for (size_t i = 0; i < count_; ++i) names.push_back(std::to_string(i));
    return names;
  }

  std::string Describe() const override {
    return bag_->path().string() + " " + topic_ + " (" + bag_->Container() + ", " + std::to_string(count_) + " images)";
  }

 private:
  std::shared_ptr<const BagFile> bag_;
  std::string topic_;
  bool compressed_;
  size_t count_;
};

std::string ChooseImageTopic(const BagFile& bag, const std::string& asked) {
  if (!asked.empty()) {
    const std::string type = bag.TypeOf(asked);
    if (!IsImageType(type)) {
      throw InputError(bag.path().string() + ": topic " + asked + " is " + type +
                       ", not sensor_msgs/Image or sensor_msgs/CompressedImage");
    }
    return asked;
  }
  std::vector<BagTopic> images;
  for (const BagTopic& t : bag.Topics()) {
    if (IsImageType(t.type)) images.push_back(t);
  }
  if (images.size() == 1) return images[0].name;
  if (images.empty()) {
    throw InputError(bag.path().string() + ": no image topic (sensor_msgs/Image or CompressedImage); the topics: " +
                     ListTopics(bag.Topics()));
  }
  throw InputError(bag.path().string() + ": " + std::to_string(images.size()) + " image topics (" + ListTopics(images) +
                   "): choose one with --topic");
}

// The camera of a CameraInfo message.
CameraCalibration CalibrationFromCameraInfo(const CameraInfoMessage& info, const std::string& where) {
  if (info.binning_x > 1 || info.binning_y > 1 || info.roi_width != 0 || info.roi_height != 0) {
    throw InputError(where + ": a camera_info with binning or a region of interest (give the calibration with --calib)");
  }
  CameraCalibration c;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.fx = info.k[0];
  c.fy = info.k[4];
  c.cx = info.k[2];
  c.cy = info.k[5];
  const std::vector<double>& d = info.d;
  const bool no_distortion = std::all_of(d.begin(), d.end(), [](double v) { return v == 0.0; });
  if (no_distortion) {
    c.model = CameraModel::kPinhole;
  } else if (info.distortion_model == "plumb_bob" && d.size() == 5) {
    c.model = CameraModel::kRadTan;
    c.distortion = d;
  } else if (info.distortion_model == "rational_polynomial" && d.size() >= 8 &&
             std::all_of(d.begin() + 5, d.end(), [](double v) { return v == 0.0; })) {
    c.model = CameraModel::kRadTan;
    c.distortion.assign(d.begin(), d.begin() + 5);
  } else if (info.distortion_model == "equidistant" && d.size() == 4) {
    c.model = CameraModel::kEquidistant;
    c.distortion = d;
  } else {
    throw InputError(where + ": distortion model '" + info.distortion_model + "' with " + std::to_string(d.size()) +
                     " coefficients is not one dsm reads (plumb_bob, rational_polynomial without k4..k6, "
                     "equidistant): give the calibration with --calib");
  }
  c.Validate(where);
  return c;
}

CameraCalibration ReadCameraInfo(const BagFile& bag, const std::string& image_topic) {
  std::vector<BagTopic> infos;
  for (const BagTopic& t : bag.Topics()) {
    if (t.type == "sensor_msgs/CameraInfo") infos.push_back(t);
  }
  // image_transport's names: <camera>/image_raw, <camera>/image_raw/compressed, <camera>/camera_info.
  std::string camera = image_topic;
  const std::string compressed = "/compressed";
  if (camera.size() > compressed.size() && camera.compare(camera.size() - compressed.size(), compressed.size(), compressed) == 0) {
    camera.resize(camera.size() - compressed.size());
  }
  const size_t slash = camera.rfind('/');
  const std::string sibling = (slash == std::string::npos ? std::string() : camera.substr(0, slash)) + "/camera_info";
  std::string topic;
  for (const BagTopic& t : infos) {
    if (t.name == sibling) topic = t.name;
  }
  if (topic.empty() && infos.size() == 1) topic = infos[0].name;
  if (topic.empty()) {
    throw InputError(bag.path().string() + ": no calibration for " + image_topic + ": give one with --calib " +
                     (infos.empty() ? std::string("(the recording has no sensor_msgs/CameraInfo)")
                                    : "(no " + sibling + " among the CameraInfo topics " + ListTopics(infos) + ")"));
  }
  const std::string where = bag.path().string() + " " + topic + " message 0";
  const std::vector<uint8_t> bytes = bag.Read(topic, 0);
  WireReader in(bytes.data(), bytes.size(), bag.WireOf(topic), where);
  return CalibrationFromCameraInfo(DecodeCameraInfo(in), where);
}

}  // namespace

bool HasImageTopic(const BagFile& bag) {
  const std::vector<BagTopic> topics = bag.Topics();
  return std::any_of(topics.begin(), topics.end(), [](const BagTopic& t) { return IsImageType(t.type); });
}

Trajectory ReadBagGroundTruth(const BagFile& bag, const BagInput& input) {
  if (input.gt_parent.empty() != input.gt_child.empty()) throw InputError("--gt-frames needs two frames, PARENT CHILD");
  if (!input.gt_topic.empty() && !input.gt_parent.empty()) {
    throw InputError("--gt-topic and --gt-frames both name a ground truth: give one");
  }
  if (!input.gt_topic.empty()) return ReadPoseTopic(bag, input.gt_topic);
  if (!input.gt_parent.empty()) return ReadTfChain(bag, input.gt_parent, input.gt_child);
  return {};
}

Dataset OpenBag(const fs::path& path, const BagInput& input) {
  const std::shared_ptr<const BagFile> bag = OpenBagFile(path);
  Dataset d;
  d.format = "bag";
  d.root = path;
  const std::string topic = ChooseImageTopic(*bag, input.topic);
  const bool compressed = bag->TypeOf(topic) == "sensor_msgs/CompressedImage";

  // The calibration, and the camera's pose on the tracked body when it says.
  std::optional<SE3d> body_from_cam;
  if (!input.calib.empty()) {
    d.calibration_file = input.calib;
    if (LoadYamlMapping(input.calib)["T_BS"]) {
      const EurocSensor sensor = ReadEurocSensorYaml(input.calib);
      d.camera = sensor.camera;
      body_from_cam = sensor.body_from_cam;
    } else {
      const CameraYaml yaml = ReadCameraYaml(input.calib);
      d.camera = yaml.camera;
      if (yaml.line_delay_us) {
        d.line_delay_us = *yaml.line_delay_us;
        d.line_delay_source = LineDelaySource::kCalibration;
      }
    }
  } else {
    d.camera = ReadCameraInfo(*bag, topic);
  }
  if (!input.gt.IsDefault() && !body_from_cam) {
    throw InputError("--gt-frame / --gt-quaternion read the ground truth against EuRoC's sensor.yaml (--calib)");
  }

  // Frames: log times where the recording's header stamps are its log times, else the stamps.
  const std::vector<int64_t> log_times = bag->LogTimes(topic);
  if (log_times.empty()) throw InputError(path.string() + ": topic " + topic + " has no message");
  const size_t last = log_times.size() - 1;
  const DecodedFrame first = DecodeFrame(*bag, topic, compressed, 0, true);
  const bool logged_at_stamp = first.stamp_ns == log_times[0] &&
                               DecodeFrame(*bag, topic, compressed, last, false).stamp_ns == log_times[last];
  for (size_t i = 0; i < log_times.size(); ++i) {
    const int64_t t = logged_at_stamp ? log_times[i] : DecodeFrame(*bag, topic, compressed, i, false).stamp_ns;
    d.frames.push_back({t, std::to_string(i), 0.0});
  }
  ValidateFrames(d.frames, path.string() + " " + topic);
  if (first.image.width() != d.camera.width || first.image.height() != d.camera.height) {
    throw ImageSizeError(path.string() + " " + topic + ": images are " + std::to_string(first.image.width()) + "x" +
                         std::to_string(first.image.height()) + " but the calibration" +
                         (input.calib.empty() ? std::string() : " " + input.calib.string()) + " says " +
                         std::to_string(d.camera.width) + "x" + std::to_string(d.camera.height));
  }
  d.images = std::make_shared<BagImageStore>(bag, topic, compressed, log_times.size());

  // Ground truth.
  const Trajectory poses = ReadBagGroundTruth(*bag, input);
  for (size_t i = 0; i < poses.size(); ++i) {
    SE3d pose = poses.poses[i];
    if (body_from_cam) {
      if (input.gt.quaternion == GtQuaternion::kJpl) pose = SE3d(pose.So3().Inverse(), pose.Translation());
      if (input.gt.frame == GtFrame::kBody) pose = pose * *body_from_cam;
    }
    d.ground_truth.Add(poses.stamps_ns[i], pose);
  }
  return d;
}

std::string DescribeBagTopics(const BagFile& bag) {
  std::string out = bag.path().string() + " (" + bag.Container() + ")\n";
  const std::vector<BagTopic> topics = bag.Topics();
  size_t name_width = 5, type_width = 4;
  for (const BagTopic& t : topics) {
    name_width = std::max(name_width, t.name.size());
    type_width = std::max(type_width, t.type.size());
  }
  std::ostringstream lines;
  for (const BagTopic& t : topics) {
    lines << "  " << std::left << std::setw(static_cast<int>(name_width)) << t.name << "  "
          << std::setw(static_cast<int>(type_width)) << t.type << "  " << t.count << "\n";
  }
  out += lines.str();
  return out;
}

}  // namespace dsm
