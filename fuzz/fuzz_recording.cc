// SPDX-License-Identifier: MIT
#include "fuzz/fuzz_recording.h"

#include <memory>
#include <string>

#include "dsm/bag/bag_dataset.h"
#include "dsm/bag/bag_file.h"
#include "dsm/bag/image_message.h"
#include "dsm/bag/messages.h"
#include "dsm/util/check.h"
#include "fuzz/fuzz_input.h"

namespace dsm::fuzz {

namespace {

void DecodeAs(const std::string& type, const std::vector<uint8_t>& bytes, WireFormat wire) {
  WireReader in(bytes.data(), bytes.size(), wire, "fuzz message");
  if (type == "sensor_msgs/Image") {
    const Image<uint8_t> image = ImageMessageToGray8(DecodeImage(in), "fuzz image");
    DSM_CHECK(image.width() > 0 && image.height() > 0, "an empty image accepted");
  } else if (type == "sensor_msgs/CompressedImage") {
    CompressedImageToGray8(DecodeCompressedImage(in), "fuzz compressed image");
  } else if (type == "sensor_msgs/CameraInfo") {
    DecodeCameraInfo(in);
  } else if (IsPoseType(type)) {
    for (const StampedPose& p : DecodePoses(type, in)) {
      DSM_CHECK(p.pose.Translation().allFinite(), "a pose with a non-finite position accepted");
    }
  }
}

}  // namespace

void FuzzRecording(const std::filesystem::path& file, const uint8_t* data, size_t size) {
  WriteFile(file, std::string_view(reinterpret_cast<const char*>(data), size));
  CheckRecording(file);
}

void CheckRecording(const std::filesystem::path& file) {
  std::string pose_topic;
  try {
    const std::unique_ptr<BagFile> bag = OpenBagFile(file);
    for (const BagTopic& topic : bag->Topics()) {
      const size_t count = bag->LogTimes(topic.name).size();
      DSM_CHECK(count == topic.count, "a topic's index and its count differ");
      if (IsPoseType(topic.type) && topic.type != "tf2_msgs/TFMessage") pose_topic = topic.name;
      for (size_t i = 0; i < count && i < 16; ++i) {
        try {
          DecodeAs(topic.type, bag->Read(topic.name, i), bag->WireOf(topic.name));
        } catch (const InputError& e) {
          Report(std::string("message rejected: ") + e.what());
        }
      }
    }
  } catch (const InputError& e) {
    Report(std::string("rejected: ") + e.what());
    return;
  }
  try {
    BagInput input;
    input.gt_topic = pose_topic;
    const Dataset dataset = OpenBag(file, input);
    CheckDataset(dataset);
    Report("accepted: " + std::to_string(dataset.size()) + " frames");
  } catch (const InputError& e) {
    Report(std::string("dataset rejected: ") + e.what());
  }
}

}  // namespace dsm::fuzz
