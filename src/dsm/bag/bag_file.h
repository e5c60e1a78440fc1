// SPDX-License-Identifier: MIT
// A robot recording: messages on named topics, each of a ROS message type. Containers:
//   ROS 1 bag    a `.bag` file (format 2.0; chunks uncompressed, bz2 or lz4; ros1_bag.h), messages
//                in the ROS 1 serialization
//   MCAP         a `.mcap` file (mcap_file.h) of `cdr` (ROS 2) or `ros1` messages
//   ROS 2 bag    a folder with rosbag2's `metadata.yaml` and the `.db3` (SQLite) or `.mcap` files
//                it lists (ros2_bag.h), messages in CDR; a `.db3` file alone reads too
// Message types are named the ROS 1 way ("sensor_msgs/Image"; ROS 2's "sensor_msgs/msg/Image"
// is read as that). Opening reads the container's index, not its messages: the messages of a
// topic are read one at a time, when asked for.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dsm/bag/wire.h"

namespace dsm {

struct BagTopic {
  std::string name;
  std::string type;      // "sensor_msgs/Image"
  std::string encoding;  // How its messages are serialized: "ros1", "cdr" (the ones dsm reads), ...
  uint64_t count = 0;
};

class BagFile {
 public:
  virtual ~BagFile() = default;
  const std::filesystem::path& path() const { return path_; }
  // "ROS 1 bag", "MCAP", "ROS 2 bag (SQLite)", ...
  virtual std::string Container() const = 0;
  // Every topic with at least one message, sorted by name.
  std::vector<BagTopic> Topics() const;
  // The log (record) times of `topic`'s messages in nanoseconds, in the order the messages are
  // numbered below (log time, then position in the file), from the index alone. Throws InputError
  // naming the file and topic when the topic is not in the recording.
  virtual std::vector<int64_t> LogTimes(const std::string& topic) const = 0;
  // The serialized bytes of message `index` of `topic` (numbered as LogTimes); throws InputError
  // for a topic or message that is not there, and DamagedRecordingError (io/dataset.h) naming the
  // file, topic and message when the container cannot give it (a damaged chunk, an index that
  // points outside the file). Safe to call from several threads.
  std::vector<uint8_t> Read(const std::string& topic, size_t index) const;

  // The type of `topic`; throws InputError naming the file and the topics there are when it is
  // not in the recording.
  std::string TypeOf(const std::string& topic) const;
  // How `topic`'s messages are serialized; throws InputError naming the file and topic for a
  // missing topic or an encoding dsm does not read.
  WireFormat WireOf(const std::string& topic) const;

 protected:
  explicit BagFile(std::filesystem::path path) : path_(std::move(path)) {}
  // Message `index` (in range) of `topic`; errors are InputError (Read makes them
  // DamagedRecordingError), their messages best begin with `what` ("FILE topic T message I").
  virtual std::vector<uint8_t> ReadMessage(const std::string& topic, size_t index, const std::string& what) const = 0;
  // Adds `count` messages of `topic` (its name, type and encoding) to what Topics() lists; throws
  // InputError naming the file when the topic was added before with another type or encoding.
  void AddTopic(const BagTopic& topic);
  // The topics as added; for the readers that count them afterwards.
  std::map<std::string, BagTopic>& topics() { return topics_; }

 private:
  std::filesystem::path path_;
  std::map<std::string, BagTopic> topics_;
};

// Whether `path` is a recording OpenBagFile reads: a file ending in .bag, .mcap or .db3, or a
// folder with a metadata.yaml.
bool IsBagPath(const std::filesystem::path& path);

// Opens the recording at `path`; throws InputError naming the file and what is wrong (not a bag,
// truncated, an unsupported version or compression).
std::unique_ptr<BagFile> OpenBagFile(const std::filesystem::path& path);

// ROS 2's "pkg/msg/Type" as "pkg/Type"; other names unchanged.
std::string RosTypeName(const std::string& type);

}  // namespace dsm
