// SPDX-License-Identifier: MIT
#include "dsm/bag/decompress.h"

#include <bzlib.h>
#include <lz4frame.h>
#include <zstd.h>

#include <climits>
#include <cstring>

#include "dsm/util/check.h"

namespace dsm {

namespace {

std::vector<uint8_t> Bz2(const uint8_t* data, size_t size, size_t out_size, const std::string& where) {
  if (size > UINT_MAX || out_size > UINT_MAX) throw InputError(where + ": a bz2 chunk over 4 GB");
  std::vector<uint8_t> out(out_size);
  unsigned int produced = static_cast<unsigned int>(out_size);
  const int status = BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(out.data()), &produced,
                                                const_cast<char*>(reinterpret_cast<const char*>(data)),
                                                static_cast<unsigned int>(size), 0, 0);
  if (status != BZ_OK || produced != out_size) {
    throw InputError(where + ": the bz2 chunk does not decompress" +
                     (status == BZ_OK ? " to its stated size" : " (bzip2 error " + std::to_string(status) + ")"));
  }
  return out;
}

std::vector<uint8_t> Lz4(const uint8_t* data, size_t size, size_t out_size, const std::string& where) {
  LZ4F_dctx* context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION))) throw std::bad_alloc();
  std::vector<uint8_t> out(out_size);
  size_t in_pos = 0, out_pos = 0, hint = 1;
  std::string error;
  while (hint != 0 && error.empty()) {
    size_t in_left = size - in_pos, out_left = out_size - out_pos;
    hint = LZ4F_decompress(context, out.data() + out_pos, &out_left, data + in_pos, &in_left, nullptr);
    if (LZ4F_isError(hint)) {
      error = LZ4F_getErrorName(hint);
    } else if (in_left == 0 && out_left == 0 && hint != 0) {
      error = in_pos == size ? "the data ends early" : "more data than the stated size";
    }
    in_pos += in_left;
    out_pos += out_left;
  }
  LZ4F_freeDecompressionContext(context);
  if (error.empty() && out_pos != out_size) error = "not the stated size";
  if (!error.empty()) throw InputError(where + ": the lz4 chunk does not decompress (" + error + ")");
  return out;
}

std::vector<uint8_t> Zstd(const uint8_t* data, size_t size, size_t out_size, const std::string& where) {
  std::vector<uint8_t> out(out_size);
  const size_t produced = ZSTD_decompress(out.data(), out_size, data, size);
  if (ZSTD_isError(produced) || produced != out_size) {
    throw InputError(where + ": the zstd chunk does not decompress (" +
                     (ZSTD_isError(produced) ? std::string(ZSTD_getErrorName(produced)) : "not the stated size") + ")");
  }
  return out;
}

}  // namespace

std::vector<uint8_t> Decompress(const std::string& name, const uint8_t* data, size_t size, size_t uncompressed_size,
                                const std::string& where) {
  if (uncompressed_size > kMaxChunkBytes) {
    throw InputError(where + ": a chunk of " + std::to_string(uncompressed_size) + " bytes (over 1 GiB: damaged?)");
  }
  if (name.empty() || name == "none") {
    if (size != uncompressed_size) throw InputError(where + ": an uncompressed chunk of another size than stated");
    return std::vector<uint8_t>(data, data + size);
  }
  if (name == "bz2") return Bz2(data, size, uncompressed_size, where);
  if (name == "lz4") return Lz4(data, size, uncompressed_size, where);
  if (name == "zstd") return Zstd(data, size, uncompressed_size, where);
  throw InputError(where + ": compression '" + name + "' is not one dsm reads (none, bz2, lz4, zstd)");
}

}  // namespace dsm
