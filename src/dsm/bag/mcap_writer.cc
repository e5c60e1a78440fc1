// SPDX-License-Identifier: MIT
#include "dsm/bag/mcap_writer.h"

#include <zlib.h>
#include <zstd.h>

#include <cstring>

#include "dsm/util/check.h"

namespace dsm {

namespace {

constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
enum Op : uint8_t {
  kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kChunk = 0x06,
  kMessageIndex = 0x07, kChunkIndex = 0x08, kStatistics = 0x0B, kSummaryOffset = 0x0E, kDataEnd = 0x0F
};
constexpr size_t kChunkBytes = 1 << 20;

// Little-endian fields appended to a record's content.
struct Content {
  std::vector<uint8_t> bytes;
  template <typename T>
  Content& Put(T v) {
    const size_t at = bytes.size();
    bytes.resize(at + sizeof(T));
    std::memcpy(bytes.data() + at, &v, sizeof(T));
    return *this;
  }
  Content& String(const std::string& s) {
    Put(static_cast<uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
    return *this;
  }
  Content& Raw(const uint8_t* data, size_t size) {
    bytes.insert(bytes.end(), data, data + size);
    return *this;
  }
};

void AppendRecord(std::vector<uint8_t>* to, uint8_t op, const std::vector<uint8_t>& content) {
  Content head;
  head.Put(op).Put(static_cast<uint64_t>(content.size()));
  to->insert(to->end(), head.bytes.begin(), head.bytes.end());
  to->insert(to->end(), content.begin(), content.end());
}

}  // namespace

McapWriter::McapWriter(const std::filesystem::path& path, const std::string& profile)
    : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw InputError(path.string() + ": cannot write the MCAP file");
  out_.write(reinterpret_cast<const char*>(kMagic), sizeof(kMagic));
  position_ = sizeof(kMagic);
  WriteRecord(kHeader, Content().String(profile).String("dsm").bytes);
}

McapWriter::~McapWriter() = default;

void McapWriter::WriteRecord(uint8_t op, const std::vector<uint8_t>& content) {
  std::vector<uint8_t> record;
  AppendRecord(&record, op, content);
  out_.write(reinterpret_cast<const char*>(record.data()), static_cast<std::streamsize>(record.size()));
  position_ += record.size();
}

uint16_t McapWriter::AddSchema(const std::string& name, const std::string& encoding, const std::string& data) {
  const uint16_t id = static_cast<uint16_t>(schemas_.size() + 1);
  Content c;
  c.Put(id).String(name).String(encoding).Put(static_cast<uint32_t>(data.size()));
  c.Raw(reinterpret_cast<const uint8_t*>(data.data()), data.size());
  schemas_.push_back(c.bytes);
  WriteRecord(kSchema, c.bytes);
  return id;
}

uint16_t McapWriter::AddChannel(uint16_t schema, const std::string& topic, const std::string& message_encoding) {
  const uint16_t id = static_cast<uint16_t>(channels_.size() + 1);
  Content c;
  c.Put(id).Put(schema).String(topic).String(message_encoding).Put(uint32_t{0});  // no metadata
  channels_.push_back(c.bytes);
  channel_counts_[id] = 0;
  WriteRecord(kChannel, c.bytes);
  return id;
}

void McapWriter::AddMessage(uint16_t channel, int64_t log_time_ns, const std::vector<uint8_t>& data) {
  DSM_CHECK(!closed_ && channel >= 1 && channel <= channels_.size(), "a message on an unknown channel");
  const uint64_t t = static_cast<uint64_t>(log_time_ns);
  Content c;
  c.Put(channel).Put(static_cast<uint32_t>(channel_counts_[channel])).Put(t).Put(t).Raw(data.data(), data.size());
  chunk_index_[channel].emplace_back(t, chunk_.size());
  AppendRecord(&chunk_, kMessage, c.bytes);
  chunk_start_ = std::min(chunk_start_, t);
  chunk_end_ = std::max(chunk_end_, t);
  first_time_ = std::min(first_time_, t);
  last_time_ = std::max(last_time_, t);
  ++channel_counts_[channel];
  ++message_count_;
  if (chunk_.size() >= kChunkBytes) FlushChunk();
}

void McapWriter::FlushChunk() {
  if (chunk_.empty()) return;
  std::vector<uint8_t> compressed(ZSTD_compressBound(chunk_.size()));
  const size_t size = ZSTD_compress(compressed.data(), compressed.size(), chunk_.data(), chunk_.size(), 3);
  DSM_CHECK(!ZSTD_isError(size), "zstd compression failed");
  compressed.resize(size);
  const uint32_t crc = static_cast<uint32_t>(crc32(crc32(0L, Z_NULL, 0), chunk_.data(), static_cast<uInt>(chunk_.size())));
  ChunkIndex index{};
  index.start_time = chunk_start_;
  index.end_time = chunk_end_;
  index.offset = position_;
  index.compressed = compressed.size();
  index.uncompressed = chunk_.size();
  Content c;
  c.Put(chunk_start_).Put(chunk_end_).Put(static_cast<uint64_t>(chunk_.size())).Put(crc).String("zstd");
  c.Put(static_cast<uint64_t>(compressed.size())).Raw(compressed.data(), compressed.size());
  WriteRecord(kChunk, c.bytes);
  index.length = position_ - index.offset;
  index.index_offset_start = position_;
  for (const auto& [channel, entries] : chunk_index_) {
    index.index_offsets[channel] = position_;
    Content m;
    m.Put(channel).Put(static_cast<uint32_t>(entries.size() * 16));
    for (const auto& [time, offset] : entries) m.Put(time).Put(offset);
    WriteRecord(kMessageIndex, m.bytes);
  }
  index.index_length = position_ - index.index_offset_start;
  chunk_indexes_.push_back(index);
  chunk_.clear();
  chunk_index_.clear();
  chunk_start_ = UINT64_MAX;
  chunk_end_ = 0;
}

void McapWriter::Close() {
  if (closed_) return;
  FlushChunk();
  closed_ = true;
  WriteRecord(kDataEnd, Content().Put(uint32_t{0}).bytes);
  const uint64_t summary_start = position_;
  std::vector<std::tuple<uint8_t, uint64_t, uint64_t>> groups;  // opcode, start, length
  const auto group = [&](uint8_t op, const std::vector<std::vector<uint8_t>>& contents) {
    if (contents.empty()) return;
    const uint64_t start = position_;
    for (const auto& content : contents) WriteRecord(op, content);
    groups.emplace_back(op, start, position_ - start);
  };
  group(kSchema, schemas_);
  group(kChannel, channels_);
  Content stats;
  stats.Put(message_count_).Put(static_cast<uint16_t>(schemas_.size())).Put(static_cast<uint32_t>(channels_.size()));
  stats.Put(uint32_t{0}).Put(uint32_t{0}).Put(static_cast<uint32_t>(chunk_indexes_.size()));
  stats.Put(message_count_ ? first_time_ : uint64_t{0}).Put(last_time_);
  stats.Put(static_cast<uint32_t>(channel_counts_.size() * 10));
  for (const auto& [channel, count] : channel_counts_) stats.Put(channel).Put(count);
  group(kStatistics, {stats.bytes});
  std::vector<std::vector<uint8_t>> chunk_records;
  for (const ChunkIndex& i : chunk_indexes_) {
    Content c;
    c.Put(i.start_time).Put(i.end_time).Put(i.offset).Put(i.length);
    c.Put(static_cast<uint32_t>(i.index_offsets.size() * 10));
    for (const auto& [channel, offset] : i.index_offsets) c.Put(channel).Put(offset);
    c.Put(i.index_length).String("zstd").Put(i.compressed).Put(i.uncompressed);
    chunk_records.push_back(c.bytes);
  }
  group(kChunkIndex, chunk_records);
  const uint64_t offsets_start = position_;
  for (const auto& [op, start, length] : groups) WriteRecord(kSummaryOffset, Content().Put(op).Put(start).Put(length).bytes);
  WriteRecord(kFooter, Content().Put(summary_start).Put(offsets_start).Put(uint32_t{0}).bytes);
  out_.write(reinterpret_cast<const char*>(kMagic), sizeof(kMagic));
  out_.close();
  if (!out_) throw InputError(path_.string() + ": cannot write the MCAP file");
}

}  // namespace dsm
