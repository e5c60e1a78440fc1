// SPDX-License-Identifier: MIT
#include "dsm/mapfile/zip_archive.h"

#include <zip.h>

#include <utility>

#include "dsm/util/check.h"

namespace dsm {
namespace {

std::string ZipErrorText(int code) {
  zip_error_t error;
  zip_error_init_with_code(&error, code);
  std::string text = zip_error_strerror(&error);
  zip_error_fini(&error);
  return text;
}

// Deflate expands at most ~1032:1; a claimed size beyond this bound is not what the entry holds.
constexpr uint64_t kMaxDeflateRatio = 1100;

}  // namespace

ZipWriter::ZipWriter(std::filesystem::path file) : file_(std::move(file)) {
  int error = 0;
  archive_ = zip_open(file_.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  if (archive_ == nullptr) throw InputError(file_.string() + ": cannot write the file (" + ZipErrorText(error) + ")");
}

ZipWriter::~ZipWriter() {
  if (archive_ != nullptr) zip_discard(archive_);
}

void ZipWriter::Add(const std::string& name, std::string bytes) {
  DSM_CHECK(archive_ != nullptr, "ZipWriter::Add after Close");
  entries_.push_back(std::move(bytes));
  const std::string& data = entries_.back();
  zip_source_t* source = zip_source_buffer(archive_, data.data(), data.size(), 0);
  const zip_int64_t index = source == nullptr ? -1 : zip_file_add(archive_, name.c_str(), source, ZIP_FL_ENC_UTF_8);
  if (index < 0) {
    if (source != nullptr) zip_source_free(source);
    throw InputError(file_.string() + ": cannot add " + name + " (" + zip_strerror(archive_) + ")");
  }
  constexpr zip_uint16_t kDate19800101 = (0 << 9) | (1 << 5) | 1;  // DOS date: years since 1980, month, day.
  if (zip_set_file_compression(archive_, index, ZIP_CM_DEFLATE, 6) != 0 ||
      zip_file_set_dostime(archive_, index, 0, kDate19800101, 0) != 0) {
    throw InputError(file_.string() + ": cannot add " + name + " (" + zip_strerror(archive_) + ")");
  }
}

void ZipWriter::Close() {
  DSM_CHECK(archive_ != nullptr, "ZipWriter::Close twice");
  if (zip_close(archive_) != 0) {
    const std::string why = zip_strerror(archive_);
    zip_discard(archive_);
    archive_ = nullptr;
    throw InputError(file_.string() + ": cannot write the file (" + why + ")");
  }
  archive_ = nullptr;
  entries_.clear();
}

ZipReader::ZipReader(std::filesystem::path file, uint64_t max_entry_bytes)
    : file_(std::move(file)), max_entry_bytes_(max_entry_bytes) {
  std::error_code ec;
  const auto status = std::filesystem::status(file_, ec);
  if (ec || !std::filesystem::exists(status)) throw InputError(file_.string() + ": no such file");
  if (!std::filesystem::is_regular_file(status)) throw InputError(file_.string() + ": not a file");
  int error = 0;
  archive_ = zip_open(file_.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &error);
  if (archive_ == nullptr) {
    throw InputError(file_.string() + ": not a readable zip archive (" + ZipErrorText(error) + ")");
  }
}

ZipReader::~ZipReader() {
  if (archive_ != nullptr) zip_discard(archive_);
}

bool ZipReader::Has(const std::string& name) const { return zip_name_locate(archive_, name.c_str(), 0) >= 0; }

uint64_t ZipReader::Size(const std::string& name) const {
  zip_stat_t st;
  if (zip_stat(archive_, name.c_str(), 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE)) {
    throw InputError(file_.string() + ": " + name + " is missing");
  }
  return st.size;
}

std::string ZipReader::Read(const std::string& name) const {
  const std::string where = file_.string() + ": " + name;
  zip_stat_t st;
  if (zip_stat(archive_, name.c_str(), 0, &st) != 0) throw InputError(where + " is missing");
  if (!(st.valid & ZIP_STAT_SIZE) || !(st.valid & ZIP_STAT_COMP_SIZE)) throw InputError(where + ": no size");
  if (st.size > max_entry_bytes_) throw InputError(where + ": larger than " + std::to_string(max_entry_bytes_) + " bytes");
  if (st.size > (st.comp_size + 64) * kMaxDeflateRatio) throw InputError(where + ": its sizes disagree (damaged)");
  zip_file_t* f = zip_fopen(archive_, name.c_str(), 0);
  if (f == nullptr) throw InputError(where + ": cannot be read (" + zip_strerror(archive_) + ")");
  std::string bytes(st.size, '\0');
  const zip_int64_t n = zip_fread(f, bytes.data(), st.size);
  // One more byte read tells an entry that holds more than its header says.
  char extra;
  const zip_int64_t more = n == static_cast<zip_int64_t>(st.size) ? zip_fread(f, &extra, 1) : 0;
  const std::string why = n < 0 || more < 0 ? zip_file_strerror(f) : "";
  zip_fclose(f);
  if (n < 0 || more < 0) throw InputError(where + ": damaged (" + why + ")");
  if (n != static_cast<zip_int64_t>(st.size) || more != 0) throw InputError(where + ": truncated or damaged");
  return bytes;
}

std::vector<std::string> ZipReader::Names() const {
  std::vector<std::string> names;
  const zip_int64_t n = zip_get_num_entries(archive_, 0);
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* name = zip_get_name(archive_, i, 0);
    if (name != nullptr) names.emplace_back(name);
  }
  return names;
}

}  // namespace dsm
