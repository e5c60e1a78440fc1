// SPDX-License-Identifier: MIT
#include "dsm/bag/ros1_bag.h"

#include <map>
#include <mutex>

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "dsm/io/dataset.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

class Ros1Bag : public BagFile {
 public:
  explicit Ros1Bag(const fs::path& path) : BagFile(path) {
    Guard([&] {
      bag_.open(path.string(), rosbag::bagmode::Read);
      rosbag::View all(bag_);
      for (const rosbag::ConnectionInfo* connection : all.getConnections()) {
        BagTopic& topic = topics_[connection->topic];
        const std::string type = RosTypeName(connection->datatype);
        if (!topic.type.empty() && topic.type != type) {
          throw InputError(path.string() + ": topic " + connection->topic + " carries two types, " + topic.type +
                           " and " + connection->datatype);
        }
        topic.name = connection->topic;
        topic.type = type;
      }
      for (auto& [name, topic] : topics_) topic.count = rosbag::View(bag_, rosbag::TopicQuery(name)).size();
    }, "");
  }

  std::string Container() const override { return "ROS 1 bag"; }
  WireFormat Wire() const override { return WireFormat::kRos1; }

  std::vector<BagTopic> Topics() const override {
    std::vector<BagTopic> topics;
    for (const auto& [name, topic] : topics_) {
      if (topic.count > 0) topics.push_back(topic);
    }
    return topics;
  }

  std::vector<int64_t> LogTimes(const std::string& topic) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<int64_t> times;
    for (const rosbag::MessageInstance& m : Messages(topic)) times.push_back(static_cast<int64_t>(m.getTime().toNSec()));
    return times;
  }

  std::vector<uint8_t> Read(const std::string& topic, size_t index) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::vector<rosbag::MessageInstance>& messages = Messages(topic);
    if (index >= messages.size()) {
      throw InputError(path().string() + ": topic " + topic + " has no message " + std::to_string(index));
    }
    std::vector<uint8_t> bytes;
    Guard<DamagedRecordingError>([&] {
      const rosbag::MessageInstance& m = messages[index];
      bytes.resize(m.size());
      ros::serialization::OStream stream(bytes.data(), static_cast<uint32_t>(bytes.size()));
      m.write(stream);
    }, " topic " + topic + " message " + std::to_string(index));
    return bytes;
  }

 private:
  // Runs `f`, turning the library's exceptions into an Error naming the file and `what`.
  template <typename Error = InputError, typename F>
  void Guard(F&& f, const std::string& what) const {
    try {
      f();
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw Error(path().string() + what + ": cannot be read as a ROS 1 bag (" + e.what() + ")");
    }
  }

  // The messages of `topic` in the library's order (log time), listed once; mutex_ held.
  const std::vector<rosbag::MessageInstance>& Messages(const std::string& topic) const {
    if (!topics_.count(topic)) TypeOf(topic);  // Throws, naming the topics there are.
    auto it = messages_.find(topic);
    if (it == messages_.end()) {
      std::vector<rosbag::MessageInstance> list;
      Guard([&] {
        rosbag::View view(bag_, rosbag::TopicQuery(topic));
        for (const rosbag::MessageInstance& m : view) list.push_back(m);
      }, " topic " + topic);
      it = messages_.emplace(topic, std::move(list)).first;
    }
    return it->second;
  }

  rosbag::Bag bag_;
  std::map<std::string, BagTopic> topics_;
  mutable std::mutex mutex_;
  mutable std::map<std::string, std::vector<rosbag::MessageInstance>> messages_;
};

}  // namespace

std::unique_ptr<BagFile> OpenRos1Bag(const fs::path& path) { return std::make_unique<Ros1Bag>(path); }

}  // namespace dsm
