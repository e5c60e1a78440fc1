// SPDX-License-Identifier: MIT
// Writes an MCAP file (mcap.dev/spec, the reading side is mcap_file.h) as the MCAP tools and
// Foxglove read it whole and by index:
//   magic, Header, the data section (each Schema and Channel record where it is added, then the
//   messages in zstd-compressed chunks of about 1 MiB, each chunk followed by one Message Index
//   record per channel in it), Data End, the summary section (Schemas, Channels, Statistics,
//   Chunk Indexes), the summary offset section, Footer, magic.
// Messages are best added in log-time order (the chunks' time ranges are then disjoint).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace dsm {

class McapWriter {
 public:
  // Starts `path` (profile "ros2"); throws InputError naming it when it cannot be written.
  explicit McapWriter(const std::filesystem::path& path, const std::string& profile = "ros2");
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // A schema ("sensor_msgs/msg/Image", "ros2msg", its definition); returns its id (from 1).
  uint16_t AddSchema(const std::string& name, const std::string& encoding, const std::string& data);
  // A channel on `topic` of messages of `schema` in `message_encoding` ("cdr"); returns its id.
  uint16_t AddChannel(uint16_t schema, const std::string& topic, const std::string& message_encoding);
  void AddMessage(uint16_t channel, int64_t log_time_ns, const std::vector<uint8_t>& data);
  // Writes the last chunk, the summary and the footer; throws InputError naming the file when it
  // cannot be written. Nothing may be added after.
  void Close();

 private:
  struct ChunkIndex {
    uint64_t start_time, end_time, offset, length, index_offset_start, index_length, compressed, uncompressed;
    std::map<uint16_t, uint64_t> index_offsets;
  };
  void WriteRecord(uint8_t op, const std::vector<uint8_t>& content);
  void FlushChunk();

  std::filesystem::path path_;
  std::ofstream out_;
  uint64_t position_ = 0;
  bool closed_ = false;
  std::vector<std::vector<uint8_t>> schemas_, channels_;  // Their records' contents, for the summary.
  std::map<uint16_t, uint64_t> channel_counts_;
  uint64_t message_count_ = 0, first_time_ = UINT64_MAX, last_time_ = 0;
  // The chunk being filled: its records, each channel's (log time, offset) entries, its time span.
  std::vector<uint8_t> chunk_;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;
  uint64_t chunk_start_ = UINT64_MAX, chunk_end_ = 0;
  std::vector<ChunkIndex> chunk_indexes_;
};

}  // namespace dsm
