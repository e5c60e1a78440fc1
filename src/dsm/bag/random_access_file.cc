// SPDX-License-Identifier: MIT
#include "dsm/bag/random_access_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "dsm/util/check.h"

namespace dsm {

RandomAccessFile::RandomAccessFile(const std::filesystem::path& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  struct stat st {};
  if (fd_ < 0 || ::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    const std::string reason = fd_ < 0 ? std::strerror(errno) : "not a regular file";
    if (fd_ >= 0) ::close(fd_);
    throw InputError(path.string() + ": cannot open (" + reason + ")");
  }
  size_ = static_cast<uint64_t>(st.st_size);
}

RandomAccessFile::~RandomAccessFile() { ::close(fd_); }

std::vector<uint8_t> RandomAccessFile::Read(uint64_t offset, uint64_t n, const std::string& what) const {
  if (offset > size_ || n > size_ - offset) {
    throw InputError(path_.string() + ": " + what + " (" + std::to_string(n) + " bytes at " + std::to_string(offset) +
                     ") lies beyond the end of the file (" + std::to_string(size_) + " bytes)");
  }
  std::vector<uint8_t> bytes(static_cast<size_t>(n));
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t got = ::pread(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) throw InputError(path_.string() + ": cannot read " + what + " (" + std::strerror(got < 0 ? errno : EIO) + ")");
    done += static_cast<size_t>(got);
  }
  return bytes;
}

}  // namespace dsm
