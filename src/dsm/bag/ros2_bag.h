// SPDX-License-Identifier: MIT
// A ROS 2 bag: a folder with rosbag2's `metadata.yaml` and the files it lists
// (rosbag2_bagfile_information: storage_identifier sqlite3 | mcap, relative_file_paths), each read
// as sqlite_bag.h or mcap_file.h says; a bag split into several files reads as one recording, its
// files one after the other. Messages compressed one by one (compression_mode: message, zstd) are
// decompressed as they are read; a bag compressed file by file is refused with the command that
// undoes it.
#pragma once

#include <filesystem>
#include <memory>

#include "dsm/bag/bag_file.h"

namespace dsm {

// Throws InputError naming metadata.yaml and the key, or the file, when the bag cannot be read.
std::unique_ptr<BagFile> OpenRos2Bag(const std::filesystem::path& folder);

}  // namespace dsm
