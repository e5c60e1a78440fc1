// SPDX-License-Identifier: MIT
#include "dsm/bag/bag_file.h"

#include <algorithm>
#include <cctype>

#include "dsm/bag/mcap_file.h"
#include "dsm/bag/ros1_bag.h"
#include "dsm/bag/ros2_bag.h"
#include "dsm/bag/sqlite_bag.h"
#include "dsm/io/dataset.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

std::string LowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

std::vector<BagTopic> BagFile::Topics() const {
  std::vector<BagTopic> topics;
  for (const auto& [name, topic] : topics_) {
    if (topic.count > 0) topics.push_back(topic);
  }
  return topics;
}

void BagFile::AddTopic(const BagTopic& topic) {
  const auto it = topics_.find(topic.name);
  if (it == topics_.end()) {
    topics_[topic.name] = topic;
    return;
  }
  if (it->second.type != topic.type || it->second.encoding != topic.encoding) {
    throw InputError(path().string() + ": topic " + topic.name + " carries two types, " + it->second.type + " (" +
                     it->second.encoding + ") and " + topic.type + " (" + topic.encoding + ")");
  }
  it->second.count += topic.count;
}

std::vector<uint8_t> BagFile::Read(const std::string& topic, size_t index) const {
  const auto it = topics_.find(topic);
  if (it == topics_.end() || it->second.count == 0) TypeOf(topic);  // Throws, naming the topics there are.
  if (index >= it->second.count) {
    throw InputError(path().string() + ": topic " + topic + " has no message " + std::to_string(index));
  }
  const std::string what = path().string() + " topic " + topic + " message " + std::to_string(index);
  try {
    return ReadMessage(topic, index, what);
  } catch (const DamagedRecordingError&) {
    throw;
  } catch (const InputError& e) {
    const std::string message = e.what();
    throw DamagedRecordingError(message.rfind(what, 0) == 0 ? message : what + ": " + message);
  }
}

std::string BagFile::TypeOf(const std::string& topic) const {
  std::string names;
  for (const BagTopic& t : Topics()) {
    if (t.name == topic) return t.type;
    names += (names.empty() ? "" : ", ") + t.name;
  }
  throw InputError(path().string() + ": no topic " + topic + " (the recording has " +
                   (names.empty() ? std::string("no messages") : names) + ")");
}

WireFormat BagFile::WireOf(const std::string& topic) const {
  TypeOf(topic);
  for (const BagTopic& t : Topics()) {
    if (t.name != topic) continue;
    if (t.encoding == "ros1") return WireFormat::kRos1;
    if (t.encoding == "cdr") return WireFormat::kCdr;
    throw InputError(path().string() + ": topic " + topic + " is serialized as '" + t.encoding +
                     "', not as ROS 1 or CDR messages");
  }
  throw InputError(path().string() + ": no topic " + topic);
}

bool IsBagPath(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return fs::is_regular_file(path / "metadata.yaml", ec);
  const std::string ext = LowerExtension(path);
  return ext == ".bag" || ext == ".mcap" || ext == ".db3";
}

std::unique_ptr<BagFile> OpenBagFile(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec) && fs::is_regular_file(path / "metadata.yaml", ec)) return OpenRos2Bag(path);
  if (!fs::is_regular_file(path, ec)) throw InputError(path.string() + ": no such recording");
  const std::string ext = LowerExtension(path);
  if (ext == ".bag") return OpenRos1Bag(path);
  if (ext == ".mcap") return OpenMcapFile(path);
  if (ext == ".db3") return OpenSqliteBag(path);
  throw InputError(path.string() + ": not a recording dsm reads (.bag, .mcap, .db3, or a ROS 2 bag's folder)");
}

std::string RosTypeName(const std::string& type) {
  const size_t msg = type.find("/msg/");
  return msg == std::string::npos ? type : type.substr(0, msg) + type.substr(msg + 4);
}

}  // namespace dsm
