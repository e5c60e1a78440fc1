// SPDX-License-Identifier: MIT
#include "dsm/bag/mcap_file.h"

#include <zlib.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <optional>
#include <tuple>

#include "dsm/bag/byte_span.h"
#include "dsm/bag/decompress.h"
#include "dsm/bag/random_access_file.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
enum Op : uint8_t {
  kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kChunk = 0x06,
  kMessageIndex = 0x07, kChunkIndex = 0x08, kDataEnd = 0x0F
};
constexpr uint64_t kFooterRecordBytes = 1 + 8 + 20;
// Records other than chunks and messages hold a few names and numbers: larger is damage.
constexpr uint64_t kMaxSmallRecordBytes = 64u << 20;

std::string McapString(ByteSpan& in) { return in.String(in.U32()); }

struct Record {
  uint8_t op;
  ByteSpan content;
};

// The next record of `in` (opcode, u64 length, content).
Record NextRecord(ByteSpan& in) {
  const uint8_t op = in.U8();
  const uint64_t length = in.U64();
  return {op, in.Sub(length, in.what() + ": record " + std::to_string(op) + " at " + std::to_string(in.position() - 9))};
}

uint32_t Crc32(const std::vector<uint8_t>& bytes) {
  uLong crc = crc32(0L, Z_NULL, 0);
  size_t done = 0;
  while (done < bytes.size()) {
    const uInt n = static_cast<uInt>(std::min<size_t>(bytes.size() - done, 1u << 30));
    crc = crc32(crc, bytes.data() + done, n);
    done += n;
  }
  return static_cast<uint32_t>(crc);
}

class McapFile : public BagFile {
 public:
  explicit McapFile(const fs::path& path) : BagFile(path), file_(path) {
    const uint64_t size = file_.size();
    const auto magic_at = [&](uint64_t offset) {
      if (size < offset + 8) return false;
      const std::vector<uint8_t> m = file_.Read(offset, 8, "the magic bytes");
      return std::equal(m.begin(), m.end(), kMagic);
    };
    if (!magic_at(0)) throw InputError(path.string() + ": not an MCAP file (no MCAP magic at its start)");
    std::optional<uint64_t> summary_start;
    if (size >= 8 + kFooterRecordBytes + 8 && magic_at(size - 8)) {
      const std::vector<uint8_t> footer = file_.Read(size - 8 - kFooterRecordBytes, kFooterRecordBytes, "the footer");
      ByteSpan in(footer.data(), footer.size(), path.string() + ": the footer");
      if (in.U8() == kFooter && in.U64() == 20) {
        const uint64_t start = in.U64();
        if (start != 0 && start < size - 8 - kFooterRecordBytes) summary_start = start;
      }
    }
    // With an index, the summary; without one (or where it lacks message indexes) a pass over
    // the data section.
    if (!(summary_start && ReadSummary(*summary_start))) ScanDataSection();
    for (auto& [channel, list] : messages_) {
      std::stable_sort(list.begin(), list.end(), [](const Entry& a, const Entry& b) {
        return std::tie(a.log_time, a.chunk, a.offset) < std::tie(b.log_time, b.chunk, b.offset);
      });
    }
    for (const auto& [id, channel] : channels_) {
      const auto it = messages_.find(id);
      const uint64_t count = it == messages_.end() ? 0 : it->second.size();
      AddTopic({channel.topic, channel.type, channel.encoding, count});
    }
  }

  std::string Container() const override { return "MCAP"; }

  std::vector<int64_t> LogTimes(const std::string& topic) const override {
    std::vector<int64_t> times;
    for (const Entry& e : Entries(topic)) times.push_back(static_cast<int64_t>(e.log_time));
    return times;
  }

  std::vector<uint8_t> ReadMessage(const std::string& topic, size_t index, const std::string& what) const override {
    const Entry& entry = Entries(topic)[index];
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<uint8_t> top_level;
    const std::vector<uint8_t>* bytes = &top_level;
    if (entry.chunk >= 0) {
      bytes = &ChunkRecords(static_cast<size_t>(entry.chunk), what);
    } else {
      top_level = file_.Read(entry.offset, entry.length, "a message");
    }
    ByteSpan in(bytes->data(), bytes->size(), what);
    in.Take(entry.chunk >= 0 ? entry.offset : 0);
    Record r = NextRecord(in);
    if (r.op != kMessage) throw InputError(what + ": the index points to a record that is not a message");
    const uint16_t channel = r.content.U16();
    r.content.Take(4 + 8 + 8);  // sequence, log_time, publish_time
    if (channels_.count(channel) == 0 || channels_.at(channel).topic != topic) {
      throw InputError(what + ": the index points to a message of another channel");
    }
    const size_t size = r.content.remaining();
    const uint8_t* data = r.content.Take(size);
    return std::vector<uint8_t>(data, data + size);
  }

 private:
  struct Channel {
    std::string topic, type, encoding;
  };
  struct ChunkPlace {
    uint64_t offset = 0, length = 0;  // The chunk record's, opcode included.
  };
  // A message: in chunk `chunk` at `offset` into its records, or (chunk -1) a record in the data
  // section at file offset `offset` of `length` bytes.
  struct Entry {
    uint64_t log_time;
    int64_t chunk;
    uint64_t offset;
    uint64_t length;
  };

  void AddSchema(ByteSpan in) {
    const uint16_t id = in.U16();
    const std::string name = McapString(in);
    schemas_[id] = RosTypeName(name);
  }

  void AddChannel(ByteSpan in) {
    const uint16_t id = in.U16();
    const uint16_t schema = in.U16();
    Channel c;
    c.topic = McapString(in);
    c.encoding = McapString(in);
    const auto s = schemas_.find(schema);
    c.type = s == schemas_.end() ? "(no schema)" : s->second;
    channels_[id] = c;
  }

  // Reads the summary's schemas, channels and chunk indexes, then the message indexes; false when
  // the summary has no chunk index or a chunk without message indexes (a pass over the data
  // section finds the messages then).
  bool ReadSummary(uint64_t start) {
    const uint64_t end = file_.size() - 8 - kFooterRecordBytes;
    if (end - start > kMaxSmallRecordBytes * 16) throw InputError(path().string() + ": a summary section of implausible size");
    const std::vector<uint8_t> bytes = file_.Read(start, end - start, "the summary section");
    ByteSpan in(bytes.data(), bytes.size(), path().string() + ": the summary section");
    std::vector<std::pair<ChunkPlace, std::map<uint16_t, uint64_t>>> chunks;
    while (!in.done()) {
      Record r = NextRecord(in);
      if (r.op == kSchema) AddSchema(r.content);
      if (r.op == kChannel) AddChannel(r.content);
      if (r.op == kChunkIndex) {
        r.content.Take(16);  // message start and end time
        ChunkPlace place{r.content.U64(), r.content.U64()};
        ByteSpan offsets = r.content.Sub(r.content.U32(), r.content.what());
        std::map<uint16_t, uint64_t> index_offsets;
        while (!offsets.done()) {
          const uint16_t channel = offsets.U16();
          index_offsets[channel] = offsets.U64();
        }
        chunks.emplace_back(place, index_offsets);
      }
    }
    if (chunks.empty()) return false;
    for (const auto& [place, index_offsets] : chunks) {
      if (index_offsets.empty()) return false;
    }
    for (const auto& [place, index_offsets] : chunks) {
      const int64_t chunk = static_cast<int64_t>(chunks_.size());
      chunks_.push_back(place);
      for (const auto& [channel, offset] : index_offsets) {
        const std::string what = "the message index at " + std::to_string(offset);
        const std::vector<uint8_t> head = file_.Read(offset, 9, what);
        ByteSpan h(head.data(), head.size(), path().string() + ": " + what);
        if (h.U8() != kMessageIndex) throw InputError(h.what() + ": not a message index record");
        const uint64_t length = h.U64();
        if (length > kMaxSmallRecordBytes) throw InputError(h.what() + ": a message index of implausible size");
        const std::vector<uint8_t> content = file_.Read(offset + 9, length, what);
        ByteSpan c(content.data(), content.size(), h.what());
        if (c.U16() != channel) throw InputError(h.what() + ": the index of another channel");
        ByteSpan records = c.Sub(c.U32(), h.what());
        if (records.size() % 16 != 0) throw InputError(h.what() + ": entries of another size than 16 bytes");
        std::vector<Entry>& list = messages_[channel];
        while (!records.done()) {
          const uint64_t log_time = records.U64();
          list.push_back({log_time, chunk, records.U64(), 0});
        }
      }
    }
    for (const auto& [channel, list] : messages_) {
      if (channels_.count(channel) == 0) {
        throw InputError(path().string() + ": messages indexed for channel " + std::to_string(channel) +
                         ", which the summary does not describe");
      }
    }
    return true;
  }

  // A message record's channel and log time (its first 14 bytes of content), listed as `entry`.
  void AddMessage(ByteSpan content, Entry entry) {
    const uint16_t channel = content.U16();
    content.U32();  // sequence
    entry.log_time = content.U64();
    if (channels_.count(channel) == 0) {
      throw InputError(content.what() + ": a message on channel " + std::to_string(channel) + " before its channel record");
    }
    messages_[channel].push_back(entry);
  }

  // The records of a chunk: schemas, channels and messages.
  void ScanChunk(ByteSpan in, int64_t chunk) {
    while (!in.done()) {
      const size_t at = in.position();
      const Record r = NextRecord(in);
      if (r.op == kSchema) AddSchema(r.content);
      if (r.op == kChannel) AddChannel(r.content);
      if (r.op == kMessage) AddMessage(r.content, {0, chunk, at, 0});
    }
  }

  // The data section read through record by record from the header on (a message's data is not
  // read; each chunk is decompressed).
  void ScanDataSection() {
    schemas_.clear();
    channels_.clear();
    messages_.clear();
    chunks_.clear();
    bool first = true;
    for (uint64_t at = 8; at + 8 < file_.size();) {
      const std::string where = "the record at " + std::to_string(at);
      const std::vector<uint8_t> head = file_.Read(at, 9, where);
      ByteSpan h(head.data(), head.size(), path().string() + ": " + where);
      const uint8_t op = h.U8();
      const uint64_t length = h.U64();
      if (length > file_.size() - (at + 9)) throw InputError(h.what() + ": it runs past the end of the file");
      if (first && op != kHeader) throw InputError(path().string() + ": the header record is missing");
      first = false;
      if (op == kDataEnd || op == kFooter) return;
      const bool whole = op == kSchema || op == kChannel || op == kChunk;
      if (op == kChunk ? length > kMaxChunkBytes + kMaxSmallRecordBytes : whole && length > kMaxSmallRecordBytes) {
        throw InputError(h.what() + ": a record of implausible size");
      }
      const std::vector<uint8_t> content = file_.Read(at + 9, whole ? length : std::min<uint64_t>(length, 14), where);
      ByteSpan c(content.data(), content.size(), h.what());
      if (op == kSchema) AddSchema(c);
      if (op == kChannel) AddChannel(c);
      if (op == kMessage) AddMessage(c, {0, -1, at, 9 + length});
      if (op == kChunk) {
        const int64_t index = static_cast<int64_t>(chunks_.size());
        chunks_.push_back({at, 9 + length});
        const std::vector<uint8_t> records = DecompressChunk(c);
        ScanChunk(ByteSpan(records.data(), records.size(), h.what()), index);
      }
      at += 9 + length;
    }
  }

  // A chunk record's content: its records, decompressed and checked against its CRC.
  std::vector<uint8_t> DecompressChunk(ByteSpan content) const {
    content.Take(16);  // message start and end time
    const uint64_t uncompressed_size = content.U64();
    const uint32_t crc = content.U32();
    const std::string compression = McapString(content);
    const uint64_t length = content.U64();
    const uint8_t* data = content.Take(length);
    std::vector<uint8_t> records = Decompress(compression, data, length, uncompressed_size, content.what());
    if (crc != 0 && Crc32(records) != crc) throw InputError(content.what() + ": its records fail their CRC-32");
    return records;
  }

  const std::vector<Entry>& Entries(const std::string& topic) const {
    TypeOf(topic);  // Throws, naming the topics there are.
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = topic_entries_.find(topic);
    if (it == topic_entries_.end()) {
      std::vector<Entry> list;
      for (const auto& [id, channel] : channels_) {
        const auto m = messages_.find(id);
        if (channel.topic == topic && m != messages_.end()) list.insert(list.end(), m->second.begin(), m->second.end());
      }
      std::stable_sort(list.begin(), list.end(), [](const Entry& a, const Entry& b) { return a.log_time < b.log_time; });
      it = topic_entries_.emplace(topic, std::move(list)).first;
    }
    return it->second;
  }

  // Chunk `index`'s records, errors naming `what`; the last one is kept. mutex_ held.
  const std::vector<uint8_t>& ChunkRecords(size_t index, const std::string& what) const {
    if (cached_chunk_ != index) {
      cached_chunk_.reset();
      const ChunkPlace& place = chunks_[index];
      if (place.length > kMaxChunkBytes + kMaxSmallRecordBytes) throw InputError(what + ": a chunk of implausible size");
      const std::vector<uint8_t> bytes = file_.Read(place.offset, place.length, "a chunk");
      ByteSpan in(bytes.data(), bytes.size(), what + " (the chunk at " + std::to_string(place.offset) + ")");
      Record r = NextRecord(in);
      if (r.op != kChunk) throw InputError(in.what() + ": the index points to a record that is not a chunk");
      cached_ = DecompressChunk(r.content);
      cached_chunk_ = index;
    }
    return cached_;
  }

  RandomAccessFile file_;
  std::map<uint16_t, std::string> schemas_;
  std::map<uint16_t, Channel> channels_;
  std::map<uint16_t, std::vector<Entry>> messages_;
  std::vector<ChunkPlace> chunks_;
  mutable std::mutex mutex_;
  mutable std::map<std::string, std::vector<Entry>> topic_entries_;
  mutable std::optional<size_t> cached_chunk_;
  mutable std::vector<uint8_t> cached_;
};

}  // namespace

std::unique_ptr<BagFile> OpenMcapFile(const fs::path& path) { return std::make_unique<McapFile>(path); }

}  // namespace dsm
