// SPDX-License-Identifier: MIT
// Zip archives through libzip, as the map file uses them: whole entries written and read by name.
//
// ZipWriter keeps the entries in memory and writes the archive at Close, into a temporary file
// that replaces `file` only once complete (libzip's way), so that a failed save leaves any older
// file as it was. Every entry is deflated and dated 1980-01-01 00:00: the same entries give the
// same bytes.
// ZipReader reads an entry whole and checks it against the CRC-32 the archive holds for it. An
// entry larger than `max_entry_bytes`, or than deflate can expand its compressed size to, is
// refused before anything is allocated (a damaged or hostile header cannot ask for gigabytes).
// Every error throws InputError naming the file (and the entry).
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <string>
#include <vector>

struct zip;

namespace dsm {

class ZipWriter {
 public:
  explicit ZipWriter(std::filesystem::path file);
  ~ZipWriter();  // Discards the archive unless Close wrote it.
  ZipWriter(const ZipWriter&) = delete;
  ZipWriter& operator=(const ZipWriter&) = delete;

  void Add(const std::string& name, std::string bytes);
  void Close();

 private:
  std::filesystem::path file_;
  struct zip* archive_ = nullptr;
  std::deque<std::string> entries_;  // libzip reads them at Close.
};

class ZipReader {
 public:
  explicit ZipReader(std::filesystem::path file, uint64_t max_entry_bytes = uint64_t{1} << 32);
  ~ZipReader();
  ZipReader(const ZipReader&) = delete;
  ZipReader& operator=(const ZipReader&) = delete;

  bool Has(const std::string& name) const;
  uint64_t Size(const std::string& name) const;  // Uncompressed.
  std::string Read(const std::string& name) const;
  std::vector<std::string> Names() const;

 private:
  std::filesystem::path file_;
  uint64_t max_entry_bytes_;
  struct zip* archive_ = nullptr;
};

}  // namespace dsm
