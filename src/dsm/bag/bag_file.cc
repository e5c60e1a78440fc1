// SPDX-License-Identifier: MIT
#include "dsm/bag/bag_file.h"

#include <algorithm>
#include <cctype>

#include "dsm/bag/ros1_bag.h"
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

std::string BagFile::TypeOf(const std::string& topic) const {
  std::string names;
  for (const BagTopic& t : Topics()) {
    if (t.name == topic) return t.type;
    names += (names.empty() ? "" : ", ") + t.name;
  }
  throw InputError(path().string() + ": no topic " + topic + " (the recording has " +
                   (names.empty() ? std::string("no messages") : names) + ")");
}

bool IsBagPath(const fs::path& path) { return LowerExtension(path) == ".bag"; }

std::unique_ptr<BagFile> OpenBagFile(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path.string() + ": no such bag file");
  if (LowerExtension(path) == ".bag") return OpenRos1Bag(path);
  throw InputError(path.string() + ": not a recording dsm reads (a ROS 1 .bag)");
}

std::string RosTypeName(const std::string& type) {
  const size_t msg = type.find("/msg/");
  return msg == std::string::npos ? type : type.substr(0, msg) + type.substr(msg + 4);
}

}  // namespace dsm
