// SPDX-License-Identifier: MIT
#include "dsm/bag/sqlite_bag.h"

#include <sqlite3.h>

#include <cstring>
#include <fstream>
#include <map>
#include <mutex>

#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

// `path` as an SQLite URI naming the file read-only and immutable (no lock, no journal).
std::string ImmutableUri(const fs::path& path) {
  std::string uri = "file:";
  for (const unsigned char c : fs::absolute(path).string()) {
    if (std::isalnum(c) || std::strchr("/-_.~", c) != nullptr) {
      uri += static_cast<char>(c);
    } else {
      char escaped[4];
      std::snprintf(escaped, sizeof(escaped), "%%%02X", c);
      uri += escaped;
    }
  }
  return uri + "?immutable=1";
}

class Statement {
 public:
  Statement(sqlite3* db, const char* sql, const std::string& where) {
    if (sqlite3_prepare_v2(db, sql, -1, &statement_, nullptr) != SQLITE_OK) {
      throw InputError(where + ": " + sqlite3_errmsg(db));
    }
  }
  ~Statement() { sqlite3_finalize(statement_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  sqlite3_stmt* get() const { return statement_; }

 private:
  sqlite3_stmt* statement_ = nullptr;
};

class SqliteBag : public BagFile {
 public:
  explicit SqliteBag(const fs::path& path) : BagFile(path) {
    char head[16] = {};
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path.string() + ": cannot open");
    if (!in.read(head, sizeof(head)) || std::memcmp(head, "SQLite format 3", 16) != 0) {
      throw InputError(path.string() + ": not an SQLite file (a ROS 2 bag's .db3 is one)");
    }
    if (sqlite3_open_v2(ImmutableUri(path).c_str(), &db_, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr) != SQLITE_OK) {
      const std::string message = db_ ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      throw InputError(path.string() + ": cannot open as SQLite (" + message + ")");
    }
    try {
      Statement topics(db_, "SELECT id, name, type, serialization_format FROM topics", Where());
      int step;
      std::map<int64_t, std::string> names;
      while ((step = sqlite3_step(topics.get())) == SQLITE_ROW) {
        BagTopic t;
        t.name = Text(topics.get(), 1);
        t.type = RosTypeName(Text(topics.get(), 2));
        t.encoding = Text(topics.get(), 3);
        if (this->topics().count(t.name)) {
          throw InputError(Where() + ": topic " + t.name + " is listed twice in its topics table");
        }
        names[sqlite3_column_int64(topics.get(), 0)] = t.name;
        AddTopic(t);
      }
      Check(step);
      Statement counts(db_, "SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id", Where());
      while ((step = sqlite3_step(counts.get())) == SQLITE_ROW) {
        const auto name = names.find(sqlite3_column_int64(counts.get(), 0));
        if (name != names.end()) {
          this->topics()[name->second].count = static_cast<uint64_t>(sqlite3_column_int64(counts.get(), 1));
        }
      }
      Check(step);
      for (const auto& [id, name] : names) topic_ids_[name] = id;
      for (const auto& [name, topic] : this->topics()) counts_[name] = topic.count;
    } catch (...) {
      sqlite3_close(db_);
      throw;
    }
  }
  ~SqliteBag() override { sqlite3_close(db_); }

  std::string Container() const override { return "ROS 2 bag file (SQLite)"; }

  std::vector<int64_t> LogTimes(const std::string& topic) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<int64_t> times;
    for (const Row& r : Rows(topic)) times.push_back(r.time_ns);
    return times;
  }

  std::vector<uint8_t> ReadMessage(const std::string& topic, size_t index, const std::string& what) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    const int64_t id = Rows(topic)[index].id;
    Statement select(db_, "SELECT data FROM messages WHERE id = ?", what);
    sqlite3_bind_int64(select.get(), 1, id);
    const int step = sqlite3_step(select.get());
    if (step != SQLITE_ROW) {
      Check(step);
      throw InputError(what + ": its row is gone");
    }
    const auto* data = static_cast<const uint8_t*>(sqlite3_column_blob(select.get(), 0));
    const int size = sqlite3_column_bytes(select.get(), 0);
    return std::vector<uint8_t>(data, data + size);
  }

 private:
  struct Row {
    int64_t id;
    int64_t time_ns;
  };

  std::string Where() const { return path().string(); }

  static std::string Text(sqlite3_stmt* statement, int column) {
    const unsigned char* text = sqlite3_column_text(statement, column);
    return text ? reinterpret_cast<const char*>(text) : "";
  }

  void Check(int step) const {
    if (step != SQLITE_DONE && step != SQLITE_ROW) throw InputError(Where() + ": " + sqlite3_errmsg(db_));
  }

  // `topic`'s rows in time order, listed once; mutex_ held.
  const std::vector<Row>& Rows(const std::string& topic) const {
    const auto id = topic_ids_.find(topic);
    if (id == topic_ids_.end()) {
      TypeOf(topic);  // Throws, naming the topics there are.
      throw InputError(Where() + ": no topic " + topic);
    }
    auto it = rows_.find(topic);
    if (it == rows_.end()) {
      std::vector<Row> rows;
      Statement select(db_, "SELECT id, timestamp FROM messages WHERE topic_id = ? ORDER BY timestamp, id", Where());
      sqlite3_bind_int64(select.get(), 1, id->second);
      int step;
      while ((step = sqlite3_step(select.get())) == SQLITE_ROW) {
        rows.push_back({sqlite3_column_int64(select.get(), 0), sqlite3_column_int64(select.get(), 1)});
      }
      Check(step);
      const uint64_t count = counts_.at(topic);
      if (rows.size() != count) {
        throw InputError(Where() + ": topic " + topic + " counts " + std::to_string(count) +
                         " messages but lists " + std::to_string(rows.size()) + " (a damaged file)");
      }
      it = rows_.emplace(topic, std::move(rows)).first;
    }
    return it->second;
  }

  sqlite3* db_ = nullptr;
  std::map<std::string, uint64_t> counts_;  // Messages per topic, as counted at opening.
  std::map<std::string, int64_t> topic_ids_;
  mutable std::mutex mutex_;
  mutable std::map<std::string, std::vector<Row>> rows_;
};

}  // namespace

std::unique_ptr<BagFile> OpenSqliteBag(const fs::path& path) { return std::make_unique<SqliteBag>(path); }

}  // namespace dsm
