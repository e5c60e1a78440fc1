// SPDX-License-Identifier: MIT
#include "dsm/run/mcap_export.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "dsm/bag/cdr_writer.h"
#include "dsm/bag/mcap_writer.h"
#include "dsm/bag/ros2_messages.h"
#include "dsm/bag/ros2_schemas.h"
#include "dsm/image/pyramid.h"

namespace dsm {

namespace {

void WritePose(CdrWriter& w, const SE3d& world_from_cam) {
  const Eigen::Vector3d t = world_from_cam.Translation();
  const Eigen::Quaterniond& q = world_from_cam.So3().Quaternion();
  for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) w.F64(v);
}

std::vector<uint8_t> PoseStamped(int64_t t, const std::string& frame, const SE3d& pose) {
  CdrWriter w;
  w.Header(t, frame);
  WritePose(w, pose);
  return w.Take();
}

std::vector<uint8_t> Transform(int64_t t, const std::string& parent, const std::string& child, const SE3d& pose) {
  CdrWriter w;
  w.Count(1);
  w.Header(t, parent);
  w.String(child);
  WritePose(w, pose);
  return w.Take();
}

std::vector<uint8_t> PointCloud(int64_t t, const std::string& frame, const PlyCloud& cloud) {
  CdrWriter w;
  w.Header(t, frame);
  w.U32(1);
  w.U32(static_cast<uint32_t>(cloud.xyz.size()));
  w.Count(4);
  const char* names[] = {"x", "y", "z", "intensity"};
  for (uint32_t i = 0; i < 4; ++i) {
    w.String(names[i]);
    w.U32(4 * i);
    w.U8(7);  // FLOAT32
    w.U32(1);
  }
  w.U8(0);
  w.U32(16);
  w.U32(static_cast<uint32_t>(16 * cloud.xyz.size()));
  std::vector<uint8_t> data(16 * cloud.xyz.size());
  for (size_t i = 0; i < cloud.xyz.size(); ++i) {
    const float grey = cloud.rgb.empty() ? 0.f : static_cast<float>(cloud.rgb[i][0]);
    const float point[4] = {cloud.xyz[i].x(), cloud.xyz[i].y(), cloud.xyz[i].z(), grey};
    std::memcpy(data.data() + 16 * i, point, sizeof(point));
  }
  w.Bytes(data.data(), data.size());
  w.U8(1);
  return w.Take();
}

std::vector<uint8_t> Path(int64_t t, const std::string& frame, const Trajectory& trajectory) {
  CdrWriter w;
  w.Header(t, frame);
  w.Count(trajectory.size());
  for (size_t i = 0; i < trajectory.size(); ++i) {
    w.Header(trajectory.stamps_ns[i], frame);
    WritePose(w, trajectory.poses[i]);
  }
  return w.Take();
}

}  // namespace

std::vector<std::pair<int64_t, Image<uint8_t>>> KeyframeImages(const Map& map) {
  std::vector<std::pair<int64_t, Image<uint8_t>>> images;
  for (int id = 0; id < map.NumKeyframes(); ++id) {
    const Keyframe& kf = map.keyframe(id);
    if (kf.retired) continue;
    const Image<uint16_t> fixed = kf.Level0();
    if (fixed.width() == 0) continue;
    Image<uint8_t> grey(fixed.width(), fixed.height());
    for (int y = 0; y < fixed.height(); ++y) {
      for (int x = 0; x < fixed.width(); ++x) {
        const float v = std::round(fixed(x, y) / ImagePyramid::kValueScale);
        grey(x, y) = static_cast<uint8_t>(std::clamp(v, 0.f, 255.f));
      }
    }
    images.emplace_back(kf.t_ns, std::move(grey));
  }
  return images;
}

std::vector<std::pair<std::string, int>> WriteRunMcap(const std::filesystem::path& path,
                                                      const std::vector<McapMap>& maps, const PinholeCamera& camera) {
  // Every message first (stamp, topic, bytes), then written in time order.
  struct Message {
    int64_t t;
    std::string topic;
    std::vector<uint8_t> bytes;
  };
  std::vector<Message> messages;
  std::map<std::string, std::string> topic_types;
  const auto add = [&](int64_t t, const std::string& topic, const std::string& type, std::vector<uint8_t> bytes) {
    topic_types[topic] = type;
    messages.push_back({t, topic, std::move(bytes)});
  };
  for (const McapMap& m : maps) {
    std::string suffix;  // "", "_1", ...
    if (m.id != 0) suffix.append("_").append(std::to_string(m.id));
    const std::string ns = m.id == 0 ? std::string("/dsm") : std::string("/dsm/map").append(suffix);
    const std::string world = std::string("map").append(suffix), cam = std::string("camera").append(suffix);
    for (size_t i = 0; i < m.frames.size(); ++i) {
      const int64_t t = m.frames.stamps_ns[i];
      add(t, ns + "/camera_pose", "geometry_msgs/msg/PoseStamped", PoseStamped(t, world, m.frames.poses[i]));
      add(t, "/tf", "tf2_msgs/msg/TFMessage", Transform(t, world, cam, m.frames.poses[i]));
    }
    for (size_t i = 0; i < m.keyframes.size(); ++i) {
      const int64_t t = m.keyframes.stamps_ns[i];
      add(t, ns + "/keyframe_pose", "geometry_msgs/msg/PoseStamped", PoseStamped(t, world, m.keyframes.poses[i]));
    }
    for (const auto& [t, image] : m.keyframe_images) {
      add(t, ns + "/keyframe_image", "sensor_msgs/msg/Image", CdrImage(t, cam, image));
      add(t, ns + "/camera_info", "sensor_msgs/msg/CameraInfo",
          CdrCameraInfo(t, cam, camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy,
                        std::vector<double>(5, 0.0)));
    }
    int64_t last = m.frames.empty() ? 0 : m.frames.stamps_ns.back();
    if (!m.keyframes.empty()) last = std::max(last, m.keyframes.stamps_ns.back());
    add(last, ns + "/map", "sensor_msgs/msg/PointCloud2", PointCloud(last, world, m.points));
    add(last, ns + "/trajectory", "nav_msgs/msg/Path", Path(last, world, m.keyframes));
  }
  std::stable_sort(messages.begin(), messages.end(), [](const Message& a, const Message& b) { return a.t < b.t; });

  McapWriter writer(path);
  std::map<std::string, uint16_t> schemas, channels;
  std::map<std::string, int> counts;
  for (const auto& [topic, type] : topic_types) {
    if (!schemas.count(type)) schemas[type] = writer.AddSchema(type, "ros2msg", Ros2Schema(type));
    channels[topic] = writer.AddChannel(schemas[type], topic, "cdr");
  }
  for (const Message& m : messages) {
    writer.AddMessage(channels[m.topic], m.t, m.bytes);
    ++counts[m.topic];
  }
  writer.Close();
  return {counts.begin(), counts.end()};
}

}  // namespace dsm
