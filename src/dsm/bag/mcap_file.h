// SPDX-License-Identifier: MIT
// An MCAP file (mcap.dev/spec, major version 0) as a recording (bag_file.h): channels of `cdr`
// (ROS 2) or `ros1` messages, schemas named by their ROS type; chunks uncompressed, lz4 (frame
// format) or zstd, checked against their CRC-32 when they state one.
//   <magic><Header><data section>[<summary section>][<summary offset section>]<Footer><magic>
// Opening reads the footer and the summary section: the schemas, the channels and the chunk
// indexes, and each chunk's message index records (which lie after the chunk, outside it), so no
// chunk is decompressed. A file without that index (written as a stream, or a summary without
// chunk indexes or message indexes) is read through once instead, each chunk decompressed to find
// its messages. A message read decompresses its chunk; the last one is kept.
#pragma once

#include <filesystem>
#include <memory>

#include "dsm/bag/bag_file.h"

namespace dsm {

// Throws InputError naming the file when it is not MCAP or its structure is damaged.
std::unique_ptr<BagFile> OpenMcapFile(const std::filesystem::path& path);

}  // namespace dsm
