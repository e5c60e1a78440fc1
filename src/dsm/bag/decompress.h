// SPDX-License-Identifier: MIT
// The compressions of recordings' chunks, each into a buffer of the size the container states:
//   bz2   ROS 1 bags (libbz2)
//   lz4   ROS 1 bags and MCAP: the LZ4 frame format (liblz4's LZ4F)
//   zstd  MCAP (libzstd)
// Each throws InputError naming `where` when the data does not decompress to exactly
// `uncompressed_size` bytes, or that size is over kMaxChunkBytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dsm {

// Chunks stated larger than this are taken for damage (a chunk holds a few messages).
constexpr size_t kMaxChunkBytes = size_t{1} << 30;

// The compression named `name` ("", "none", "bz2", "lz4", "zstd") applied to `data`; throws
// InputError naming `where` for another name.
std::vector<uint8_t> Decompress(const std::string& name, const uint8_t* data, size_t size, size_t uncompressed_size,
                                const std::string& where);

}  // namespace dsm
