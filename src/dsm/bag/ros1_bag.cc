// SPDX-License-Identifier: MIT
#include "dsm/bag/ros1_bag.h"

#include <algorithm>
#include <cstring>
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

constexpr uint8_t kOpMessageData = 0x02, kOpBagHeader = 0x03, kOpIndexData = 0x04, kOpChunk = 0x05,
                  kOpChunkInfo = 0x06, kOpConnection = 0x07;
const std::string kMagic = "#ROSBAG V2.0\n";
// Record headers hold a few fields (a connection's, its message definition): larger is damage.
constexpr uint32_t kMaxHeaderBytes = 16u << 20;

// A record's header fields ("name" -> value bytes).
using Fields = std::map<std::string, std::string>;

Fields ParseFields(ByteSpan header) {
  Fields fields;
  while (!header.done()) {
    const uint32_t length = header.U32();
    const std::string field = header.String(length);
    const size_t eq = field.find('=');
    if (eq == std::string::npos) throw InputError(header.what() + ": a header field without '='");
    fields[field.substr(0, eq)] = field.substr(eq + 1);
  }
  return fields;
}

template <typename T>
T Field(const Fields& fields, const std::string& name, const std::string& what) {
  const auto it = fields.find(name);
  if (it == fields.end() || it->second.size() != sizeof(T)) {
    throw InputError(what + ": no " + std::to_string(sizeof(T)) + "-byte field '" + name + "'");
  }
  T value;
  std::memcpy(&value, it->second.data(), sizeof(T));
  return value;
}

std::string TextField(const Fields& fields, const std::string& name, const std::string& what) {
  const auto it = fields.find(name);
  if (it == fields.end()) throw InputError(what + ": no field '" + name + "'");
  return it->second;
}

// A ROS time (sec u32, nsec u32) in nanoseconds.
int64_t TimeNs(uint64_t packed, const std::string& what) {
  const uint64_t sec = packed & 0xffffffffu, nsec = packed >> 32;
  if (nsec >= 1000000000u) throw InputError(what + ": a time with " + std::to_string(nsec) + " nanoseconds");
  return static_cast<int64_t>(sec * 1000000000u + nsec);
}

// A record in the file: its header fields and where its data lies.
struct FileRecord {
  Fields fields;
  uint8_t op = 0;
  uint64_t data_pos = 0, data_len = 0;
  uint64_t end() const { return data_pos + data_len; }
};

class Ros1Bag : public BagFile {
 public:
  explicit Ros1Bag(const fs::path& path) : BagFile(path), file_(path) {
    const std::vector<uint8_t> magic = file_.Read(0, std::min<uint64_t>(kMagic.size(), file_.size()), "the first line");
    if (std::string(magic.begin(), magic.end()) != kMagic) {
      throw InputError(path.string() + ": not a ROS 1 bag (it does not begin with '#ROSBAG V2.0')");
    }
    const FileRecord header = ReadRecord(kMagic.size(), "the bag header");
    if (header.op != kOpBagHeader) throw InputError(path.string() + ": the bag header record is missing");
    const uint64_t index_pos = Field<uint64_t>(header.fields, "index_pos", Where(kMagic.size()));
    if (index_pos < header.end() || index_pos >= file_.size()) {
      throw InputError(path.string() + ": a ROS 1 bag whose index cannot be read: truncated, or a recording that "
                       "never closed (rosbag reindex rebuilds the index)");
    }
    ReadIndex(index_pos, Field<uint32_t>(header.fields, "conn_count", Where(kMagic.size())),
              Field<uint32_t>(header.fields, "chunk_count", Where(kMagic.size())));
  }

  std::string Container() const override { return "ROS 1 bag"; }

  std::vector<int64_t> LogTimes(const std::string& topic) const override {
    std::vector<int64_t> times;
    for (const Entry& e : Entries(topic)) times.push_back(e.time_ns);
    return times;
  }

  std::vector<uint8_t> ReadMessage(const std::string& topic, size_t index, const std::string& what) const override {
    const Entry& entry = Entries(topic)[index];
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string in_chunk = what + " (the chunk at " + std::to_string(chunks_[entry.chunk].pos) + ")";
    const std::vector<uint8_t>& chunk = ChunkData(entry.chunk, in_chunk);
    ByteSpan record(chunk.data(), chunk.size(), in_chunk);
    record.Take(entry.offset);
    const Fields fields = ParseFields(record.Sub(record.U32(), record.what()));
    const auto op = fields.find("op");
    if (op == fields.end() || op->second != std::string(1, static_cast<char>(kOpMessageData))) {
      throw InputError(record.what() + ": the index points to a record that is not a message");
    }
    const uint32_t length = record.U32();
    const uint8_t* data = record.Take(length);
    return std::vector<uint8_t>(data, data + length);
  }

 private:
  struct Chunk {
    uint64_t pos = 0;
    std::string compression;
    uint32_t size = 0;
    uint64_t data_pos = 0, data_len = 0;
  };
  struct Entry {
    int64_t time_ns;
    uint32_t chunk;
    uint32_t offset;
  };

  std::string Where(uint64_t pos) const { return path().string() + ": the record at " + std::to_string(pos); }

  FileRecord ReadRecord(uint64_t pos, const std::string& what) const {
    FileRecord r;
    const std::vector<uint8_t> header_len = file_.Read(pos, 4, what);
    const uint32_t n = header_len[0] | header_len[1] << 8 | header_len[2] << 16 | uint32_t{header_len[3]} << 24;
    if (n > kMaxHeaderBytes) throw InputError(Where(pos) + ": a record header of " + std::to_string(n) + " bytes");
    const std::vector<uint8_t> header = file_.Read(pos + 4, uint64_t{n} + 4, what);
    r.fields = ParseFields(ByteSpan(header.data(), n, Where(pos)));
    const auto op = r.fields.find("op");
    if (op == r.fields.end() || op->second.size() != 1) throw InputError(Where(pos) + ": no op field");
    r.op = static_cast<uint8_t>(op->second[0]);
    std::memcpy(&r.data_len, header.data() + n, 4);
    r.data_len &= 0xffffffffu;
    r.data_pos = pos + 8 + n;
    if (r.data_len > file_.size() - std::min(file_.size(), r.data_pos)) {
      throw InputError(Where(pos) + ": its data (" + std::to_string(r.data_len) + " bytes) runs past the end of the file");
    }
    return r;
  }

  // The connections and chunk infos from index_pos to the end, then each chunk's index data.
  void ReadIndex(uint64_t index_pos, uint32_t conn_count, uint32_t chunk_count) {
    std::map<uint32_t, std::string> connection_topic;
    std::vector<std::pair<uint64_t, uint32_t>> chunk_infos;  // chunk_pos, connections in it
    for (uint64_t pos = index_pos; pos < file_.size();) {
      const FileRecord r = ReadRecord(pos, "an index record");
      if (r.op == kOpConnection) {
        const std::string topic = TextField(r.fields, "topic", Where(pos));
        const std::vector<uint8_t> data = file_.Read(r.data_pos, r.data_len, "a connection header");
        const Fields header = ParseFields(ByteSpan(data.data(), data.size(), Where(pos)));
        const std::string type = RosTypeName(TextField(header, "type", Where(pos)));
        AddTopic({topic, type, "ros1", 0});
        connection_topic[Field<uint32_t>(r.fields, "conn", Where(pos))] = topic;
      } else if (r.op == kOpChunkInfo) {
        chunk_infos.emplace_back(Field<uint64_t>(r.fields, "chunk_pos", Where(pos)),
                                 Field<uint32_t>(r.fields, "count", Where(pos)));
      }
      pos = r.end();
    }
    if (connection_topic.size() != conn_count || chunk_infos.size() != chunk_count) {
      throw InputError(path().string() + ": the bag header counts " + std::to_string(conn_count) + " connections and " +
                       std::to_string(chunk_count) + " chunks, its index holds " +
                       std::to_string(connection_topic.size()) + " and " + std::to_string(chunk_infos.size()));
    }
    for (const auto& [chunk_pos, connections] : chunk_infos) {
      const FileRecord r = ReadRecord(chunk_pos, "a chunk");
      if (r.op != kOpChunk) throw InputError(Where(chunk_pos) + ": a chunk info points to a record that is not a chunk");
      Chunk chunk{chunk_pos, TextField(r.fields, "compression", Where(chunk_pos)),
                  Field<uint32_t>(r.fields, "size", Where(chunk_pos)), r.data_pos, r.data_len};
      const uint32_t chunk_index = static_cast<uint32_t>(chunks_.size());
      chunks_.push_back(chunk);
      uint64_t pos = r.end();
      for (uint32_t k = 0; k < connections; ++k) {
        const FileRecord index = ReadRecord(pos, "a chunk's index");
        if (index.op != kOpIndexData) throw InputError(Where(pos) + ": a chunk's index data record is missing");
        const uint32_t conn = Field<uint32_t>(index.fields, "conn", Where(pos));
        const uint32_t count = Field<uint32_t>(index.fields, "count", Where(pos));
        const auto topic = connection_topic.find(conn);
        if (topic == connection_topic.end() || uint64_t{count} * 12 != index.data_len) {
          throw InputError(Where(pos) + ": an index of an unknown connection, or of another length than its count");
        }
        const std::vector<uint8_t> data = file_.Read(index.data_pos, index.data_len, "a chunk's index");
        ByteSpan entries(data.data(), data.size(), Where(pos));
        std::vector<Entry>& list = messages_[topic->second];
        for (uint32_t i = 0; i < count; ++i) {
          const int64_t time = TimeNs(entries.U64(), Where(pos));
          const uint32_t offset = entries.U32();
          if (offset >= chunk.size) throw InputError(Where(pos) + ": an index entry points past its chunk");
          list.push_back({time, chunk_index, offset});
        }
        pos = index.end();
      }
    }
    for (auto& [topic, list] : messages_) {
      std::stable_sort(list.begin(), list.end(), [](const Entry& a, const Entry& b) {
        return std::tie(a.time_ns, a.chunk, a.offset) < std::tie(b.time_ns, b.chunk, b.offset);
      });
      topics()[topic].count = list.size();
    }
  }

  const std::vector<Entry>& Entries(const std::string& topic) const {
    const auto it = messages_.find(topic);
    if (it == messages_.end()) {
      TypeOf(topic);  // Throws, naming the topics there are.
      throw InputError(path().string() + ": topic " + topic + " has no message");
    }
    return it->second;
  }

  // Chunk `index` decompressed, errors naming `what`; the last one is kept. mutex_ held.
  const std::vector<uint8_t>& ChunkData(uint32_t index, const std::string& what) const {
    if (cached_chunk_ != index) {
      cached_chunk_.reset();
      const Chunk& c = chunks_[index];
      const std::vector<uint8_t> data = file_.Read(c.data_pos, c.data_len, "the chunk at " + std::to_string(c.pos));
      cached_ = Decompress(c.compression, data.data(), data.size(), c.size, what);
      cached_chunk_ = index;
    }
    return cached_;
  }

  RandomAccessFile file_;
  std::map<std::string, std::vector<Entry>> messages_;
  std::vector<Chunk> chunks_;
  mutable std::mutex mutex_;
  mutable std::optional<uint32_t> cached_chunk_;
  mutable std::vector<uint8_t> cached_;
};

}  // namespace

std::unique_ptr<BagFile> OpenRos1Bag(const fs::path& path) { return std::make_unique<Ros1Bag>(path); }

}  // namespace dsm
