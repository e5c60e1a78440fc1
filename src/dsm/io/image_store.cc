// SPDX-License-Identifier: MIT
#include "dsm/io/image_store.h"

#include <algorithm>
#include <mutex>

#include <fcntl.h>
#include <unistd.h>
#include <zip.h>

#include "dsm/io/image_io.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

bool IsImageName(const std::string& name) {
  const auto dot = name.rfind('.');
  if (dot == std::string::npos) return false;
  std::string ext = name.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == "png" || ext == "jpg" || ext == "jpeg" || ext == "pgm" || ext == "ppm" || ext == "bmp" ||
         ext == "tif" || ext == "tiff";
}

class FolderStore : public ImageStore {
 public:
  explicit FolderStore(std::filesystem::path folder) : folder_(std::move(folder)) {
    if (!std::filesystem::is_directory(folder_)) throw InputError(folder_.string() + ": image folder not found");
  }
  Image<uint8_t> Load(const std::string& name) const override { return ReadGray8(folder_ / name); }
  void Prefetch(const std::string& name) const override {
    // The kernel reads the file into its page cache in the background (a file paged out since it
    // was last read otherwise costs its Load the disk's latency, hundreds of milliseconds).
    const int fd = open((folder_ / name).c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;  // Load reports it.
    posix_fadvise(fd, 0, 0, POSIX_FADV_WILLNEED);
    close(fd);
  }
  std::vector<std::string> List() const override {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder_)) {
      const std::string name = entry.path().filename().string();
      if (entry.is_regular_file() && IsImageName(name)) names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    return names;
  }
  std::string Describe() const override { return folder_.string(); }

 private:
  std::filesystem::path folder_;
};

class ZipStore : public ImageStore {
 public:
  explicit ZipStore(std::filesystem::path file) : file_(std::move(file)) {
    int error = 0;
    archive_ = zip_open(file_.c_str(), ZIP_RDONLY, &error);
    if (!archive_) throw InputError(file_.string() + ": cannot open the zip archive (error " + std::to_string(error) + ")");
  }
  ~ZipStore() override { zip_discard(archive_); }
  ZipStore(const ZipStore&) = delete;
  ZipStore& operator=(const ZipStore&) = delete;

  Image<uint8_t> Load(const std::string& name) const override {
    const std::string source = file_.string() + ":" + name;
    std::vector<uint8_t> bytes;
    {
      std::lock_guard<std::mutex> lock(mutex_);  // libzip archives are not thread-safe.
      zip_stat_t st;
      if (zip_stat(archive_, name.c_str(), 0, &st) != 0) throw InputError(source + ": not in the archive");
      zip_file_t* f = zip_fopen(archive_, name.c_str(), 0);
      if (!f) throw InputError(source + ": cannot open the entry");
      bytes.resize(st.size);
      const zip_int64_t n = zip_fread(f, bytes.data(), st.size);
      zip_fclose(f);
      if (n != static_cast<zip_int64_t>(st.size)) throw InputError(source + ": truncated entry");
    }
    return DecodeGray8(bytes, source);
  }
  std::vector<std::string> List() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> names;
    const zip_int64_t n = zip_get_num_entries(archive_, 0);
    for (zip_int64_t i = 0; i < n; ++i) {
      const char* name = zip_get_name(archive_, i, 0);
      if (name && IsImageName(name)) names.emplace_back(name);
    }
    std::sort(names.begin(), names.end());
    return names;
  }
  std::string Describe() const override { return file_.string(); }

 private:
  std::filesystem::path file_;
  zip_t* archive_ = nullptr;
  mutable std::mutex mutex_;
};

}  // namespace

std::shared_ptr<ImageStore> MakeFolderStore(const std::filesystem::path& folder) {
  return std::make_shared<FolderStore>(folder);
}

std::shared_ptr<ImageStore> MakeZipStore(const std::filesystem::path& zip_file) {
  return std::make_shared<ZipStore>(zip_file);
}

}  // namespace dsm
