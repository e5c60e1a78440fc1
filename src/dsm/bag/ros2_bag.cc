// SPDX-License-Identifier: MIT
#include "dsm/bag/ros2_bag.h"

#include <zstd.h>

#include <map>

#include "dsm/bag/decompress.h"
#include "dsm/bag/mcap_file.h"
#include "dsm/bag/sqlite_bag.h"
#include "dsm/io/yaml_file.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

// The files of a split bag, one after the other; each message zstd-compressed when `zstd`.
class Ros2Bag : public BagFile {
 public:
  Ros2Bag(const fs::path& folder, std::vector<std::unique_ptr<BagFile>> parts, bool zstd)
      : BagFile(folder), parts_(std::move(parts)), zstd_(zstd) {
    for (size_t p = 0; p < parts_.size(); ++p) {
      for (const BagTopic& t : parts_[p]->Topics()) {
        AddTopic(t);
        placed_[t.name].push_back({p, t.count});
      }
    }
  }

  std::string Container() const override {
    return "ROS 2 bag of " + std::to_string(parts_.size()) + (parts_.size() == 1 ? " file, " : " files, ") +
           (parts_[0]->Container() == "MCAP" ? "MCAP" : "SQLite") + (zstd_ ? ", messages compressed by zstd" : "");
  }

  std::vector<int64_t> LogTimes(const std::string& topic) const override {
    std::vector<int64_t> times;
    for (const Place& place : Places(topic)) {
      const std::vector<int64_t> part = parts_[place.part]->LogTimes(topic);
      times.insert(times.end(), part.begin(), part.end());
    }
    return times;
  }

  std::vector<uint8_t> ReadMessage(const std::string& topic, size_t index, const std::string& what) const override {
    size_t local = index;
    for (const Place& place : Places(topic)) {
      if (local < place.count) {
        std::vector<uint8_t> bytes = parts_[place.part]->Read(topic, local);
        return zstd_ ? Unzstd(bytes, what) : bytes;
      }
      local -= place.count;
    }
    throw InputError(what + ": not in the bag's files");
  }

 private:
  struct Place {
    size_t part;
    uint64_t count;
  };

  const std::vector<Place>& Places(const std::string& topic) const {
    const auto it = placed_.find(topic);
    if (it == placed_.end()) {
      TypeOf(topic);  // Throws, naming the topics there are.
      throw InputError(path().string() + ": no topic " + topic);
    }
    return it->second;
  }

  static std::vector<uint8_t> Unzstd(const std::vector<uint8_t>& bytes, const std::string& what) {
    const unsigned long long size = ZSTD_getFrameContentSize(bytes.data(), bytes.size());
    if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN) {
      throw InputError(what + ": not a zstd frame of known size");
    }
    return Decompress("zstd", bytes.data(), bytes.size(), size, what);
  }

  std::vector<std::unique_ptr<BagFile>> parts_;
  bool zstd_;
  std::map<std::string, std::vector<Place>> placed_;
};

}  // namespace

std::unique_ptr<BagFile> OpenRos2Bag(const fs::path& folder) {
  const fs::path metadata = folder / "metadata.yaml";
  const YAML::Node root = LoadYamlMapping(metadata);
  const YAML::Node info = root["rosbag2_bagfile_information"];
  if (!info || !info.IsMap()) throw InputError(metadata.string() + ": missing key 'rosbag2_bagfile_information'");
  const std::string storage = Get<std::string>(info, "storage_identifier", metadata);
  const std::string mode = info["compression_mode"] ? Get<std::string>(info, "compression_mode", metadata) : "";
  const std::string format = info["compression_format"] ? Get<std::string>(info, "compression_format", metadata) : "";
  bool zstd = false;
  if (!mode.empty() && mode != "NONE") {
    if ((mode == "MESSAGE" || mode == "message") && format == "zstd") {
      zstd = true;
    } else {
      throw InputError(metadata.string() + ": a bag compressed with compression_mode " + mode + ", compression_format " +
                       format + " is not read (messages compressed by zstd are): 'ros2 bag decompress' undoes it");
    }
  }
  const auto files = Get<std::vector<std::string>>(info, "relative_file_paths", metadata);
  if (files.empty()) throw InputError(metadata.string() + ": key 'relative_file_paths' lists no file");
  std::vector<std::unique_ptr<BagFile>> parts;
  for (const std::string& file : files) {
    const fs::path path = folder / file;
    if (storage == "sqlite3") {
      parts.push_back(OpenSqliteBag(path));
    } else if (storage == "mcap") {
      parts.push_back(OpenMcapFile(path));
    } else {
      throw InputError(metadata.string() + ": storage_identifier '" + storage + "' is not one dsm reads (sqlite3, mcap)");
    }
  }
  return std::make_unique<Ros2Bag>(folder, std::move(parts), zstd);
}

}  // namespace dsm
