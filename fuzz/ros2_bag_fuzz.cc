// SPDX-License-Identifier: MIT
// A ROS 2 bag's folder (bag/ros2_bag.h): the input is its metadata.yaml, beside a valid MCAP file
// bag_0.mcap (three 32x24 images with their CameraInfo, written once by dsm's MCAP writer); the
// folder is then read as fuzz_recording.h says.
#include <string>

#include "dsm/bag/mcap_writer.h"
#include "dsm/bag/ros2_messages.h"
#include "dsm/bag/ros2_schemas.h"
#include "fuzz/fuzz_input.h"
#include "fuzz/fuzz_recording.h"

namespace {

const std::filesystem::path& BagFolder() {
  static const std::filesystem::path folder = [] {
    const auto root = dsm::fuzz::Scratch() / "ros2_bag";
    std::filesystem::create_directories(root);
    dsm::McapWriter writer(root / "bag_0.mcap");
    const uint16_t image = writer.AddChannel(
        writer.AddSchema("sensor_msgs/msg/Image", "ros2msg", dsm::Ros2Schema("sensor_msgs/msg/Image")),
        "/cam/image_raw", "cdr");
    const uint16_t info = writer.AddChannel(
        writer.AddSchema("sensor_msgs/msg/CameraInfo", "ros2msg", dsm::Ros2Schema("sensor_msgs/msg/CameraInfo")),
        "/cam/camera_info", "cdr");
    dsm::Image<uint8_t> pixels(32, 24);
    for (int y = 0; y < 24; ++y) {
      for (int x = 0; x < 32; ++x) pixels(x, y) = static_cast<uint8_t>(((y * 32 + x) * 7) % 251);
    }
    for (int64_t i = 0; i < 3; ++i) {
      const int64_t t = 1600000000000000000 + i * 50000000;
      writer.AddMessage(info, t, dsm::CdrCameraInfo(t, "camera", 32, 24, 20.0, 20.0, 15.5, 11.5,
                                                    {0.01, -0.002, 0.0, 0.0, 0.0}));
      writer.AddMessage(image, t, dsm::CdrImage(t, "camera", pixels));
    }
    writer.Close();
    return root;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path& folder = BagFolder();
  dsm::fuzz::WriteFile(folder / "metadata.yaml", std::string_view(reinterpret_cast<const char*>(data), size));
  dsm::fuzz::CheckRecording(folder);
  return 0;
}
