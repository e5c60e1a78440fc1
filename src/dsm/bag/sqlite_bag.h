// SPDX-License-Identifier: MIT
// A ROS 2 bag's SQLite file (`.db3`, rosbag2's sqlite3 storage) as a recording (bag_file.h):
//   topics(id, name, type, serialization_format, ...)   messages(id, topic_id, timestamp, data)
// read with SQLite itself, opened read-only and immutable (a bag on read-only media opens too).
// Opening reads the topics and counts the messages per topic; a topic's message ids and times are
// listed when first asked for; a message is one row read by its id.
#pragma once

#include <filesystem>
#include <memory>

#include "dsm/bag/bag_file.h"

namespace dsm {

// Throws InputError naming the file when it is not SQLite or lacks rosbag2's tables.
std::unique_ptr<BagFile> OpenSqliteBag(const std::filesystem::path& path);

}  // namespace dsm
