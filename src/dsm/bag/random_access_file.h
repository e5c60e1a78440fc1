// SPDX-License-Identifier: MIT
// A file read at given offsets (pread), safe from several threads: what the containers' indexes
// point into. Every read is checked against the file's size.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace dsm {

class RandomAccessFile {
 public:
  // Throws InputError naming the file when it cannot be opened.
  explicit RandomAccessFile(const std::filesystem::path& path);
  ~RandomAccessFile();
  RandomAccessFile(const RandomAccessFile&) = delete;
  RandomAccessFile& operator=(const RandomAccessFile&) = delete;

  uint64_t size() const { return size_; }
  const std::filesystem::path& path() const { return path_; }
  // `n` bytes at `offset`; throws InputError naming the file and `what` when they are not all in
  // the file.
  std::vector<uint8_t> Read(uint64_t offset, uint64_t n, const std::string& what) const;

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  uint64_t size_ = 0;
};

}  // namespace dsm
