// SPDX-License-Identifier: MIT
// A ROS 1 bag, format 2.0 (bag_file.h), read from its index as the format documents it
// (wiki.ros.org/Bags/Format/2.0):
//   "#ROSBAG V2.0\n", then records: header_len u32, header (fields: len u32, "name=value"),
//   data_len u32, data. The bag header (op 3) gives index_pos; there the connection records
//   (op 7: conn, topic; data: the connection header with the type) and the chunk infos (op 6:
//   chunk_pos). Each chunk (op 5: compression none | bz2 | lz4, size) is followed by one index
//   data record per connection (op 4: conn, count; data: count x (sec u32, nsec u32, offset u32
//   into the uncompressed chunk)); there, a message data record (op 2) holds the message.
// Opening reads the bag header, the index section and the small records after each chunk; a
// message read decompresses its chunk (the last one is kept). Every length is checked against the
// file or the chunk: a damaged bag is an error, never a read outside the data.
#pragma once

#include <filesystem>
#include <memory>

#include "dsm/bag/bag_file.h"

namespace dsm {

// Throws InputError naming the file when it is not a bag of format 2.0, or its index is missing
// (a truncated bag, or a recording that never closed) or damaged.
std::unique_ptr<BagFile> OpenRos1Bag(const std::filesystem::path& path);

}  // namespace dsm
