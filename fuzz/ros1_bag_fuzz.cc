// SPDX-License-Identifier: MIT
// ROS 1 bags (bag/ros1_bag.h): the input is the whole .bag file. It is opened, every topic's
// messages (up to 16 each) are read and decoded as their type says, and then it is opened as a
// dataset the way `dsm run BAG` does (its CameraInfo as the calibration, a pose topic as the
// ground truth). Only InputError may come out; what is accepted keeps the readers' promises.
#include <memory>
#include <string>

#include "dsm/bag/bag_dataset.h"
#include "dsm/bag/bag_file.h"
#include "dsm/bag/image_message.h"
#include "dsm/bag/messages.h"
#include "dsm/util/check.h"
#include "fuzz/fuzz_input.h"

namespace {

void DecodeAs(const std::string& type, const std::vector<uint8_t>& bytes, dsm::WireFormat wire) {
  dsm::WireReader in(bytes.data(), bytes.size(), wire, "fuzz message");
  if (type == "sensor_msgs/Image") {
    const dsm::Image<uint8_t> image = dsm::ImageMessageToGray8(dsm::DecodeImage(in), "fuzz image");
    DSM_CHECK(image.width() > 0 && image.height() > 0, "an empty image accepted");
  } else if (type == "sensor_msgs/CompressedImage") {
    dsm::CompressedImageToGray8(dsm::DecodeCompressedImage(in), "fuzz compressed image");
  } else if (type == "sensor_msgs/CameraInfo") {
    dsm::DecodeCameraInfo(in);
  } else if (dsm::IsPoseType(type)) {
    for (const dsm::StampedPose& p : dsm::DecodePoses(type, in)) {
      DSM_CHECK(p.pose.Translation().allFinite(), "a pose with a non-finite position accepted");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = dsm::fuzz::Scratch() / "fuzz.bag";
  dsm::fuzz::WriteFile(path, std::string_view(reinterpret_cast<const char*>(data), size));
  std::string pose_topic;
  try {
    const std::unique_ptr<dsm::BagFile> bag = dsm::OpenBagFile(path);
    for (const dsm::BagTopic& topic : bag->Topics()) {
      const size_t count = bag->LogTimes(topic.name).size();
      DSM_CHECK(count == topic.count, "a topic's index and its count differ");
      if (dsm::IsPoseType(topic.type) && topic.type != "tf2_msgs/TFMessage") pose_topic = topic.name;
      for (size_t i = 0; i < count && i < 16; ++i) {
        try {
          DecodeAs(topic.type, bag->Read(topic.name, i), bag->Wire());
        } catch (const dsm::InputError& e) {
          dsm::fuzz::Report(std::string("message rejected: ") + e.what());
        }
      }
    }
  } catch (const dsm::InputError& e) {
    dsm::fuzz::Report(std::string("rejected: ") + e.what());
    return 0;
  }
  try {
    dsm::BagInput input;
    input.gt_topic = pose_topic;
    const dsm::Dataset dataset = dsm::OpenBag(path, input);
    dsm::fuzz::CheckDataset(dataset);
    dsm::fuzz::Report("accepted: " + std::to_string(dataset.size()) + " frames");
  } catch (const dsm::InputError& e) {
    dsm::fuzz::Report(std::string("dataset rejected: ") + e.what());
  }
  return 0;
}
