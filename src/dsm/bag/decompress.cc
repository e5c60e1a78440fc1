// SPDX-License-Identifier: MIT
#include "dsm/bag/decompress.h"

#include <bzlib.h>
#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <climits>
#include <memory>

#include "dsm/util/check.h"

namespace dsm {

namespace {

// The output of a decompression, grown as it fills (doubling, up to the stated size), so that a
// damaged chunk that states a huge size costs what it decompresses to, not what it states.
class Output {
 public:
  explicit Output(size_t stated) : stated_(stated), bytes_(std::min<size_t>(stated, size_t{1} << 20)) {}
  uint8_t* next() { return bytes_.data() + used_; }
  size_t room() const { return bytes_.size() - used_; }
  void Produced(size_t n) { used_ += n; }
  // Grows the room once it is used up (not past the stated size); false when it is reached.
  bool Grow() {
    if (room() > 0) return true;
    if (bytes_.size() >= stated_) return false;
    bytes_.resize(std::min(stated_, 2 * bytes_.size()));
    return true;
  }
  size_t used() const { return used_; }
  std::vector<uint8_t> Take() {
    bytes_.resize(used_);
    return std::move(bytes_);
  }

 private:
  size_t stated_;
  std::vector<uint8_t> bytes_;
  size_t used_ = 0;
};

std::vector<uint8_t> Bz2(const uint8_t* data, size_t size, size_t out_size, const std::string& where) {
  if (size > UINT_MAX) throw InputError(where + ": a bz2 chunk over 4 GB");
  bz_stream stream{};
  if (BZ2_bzDecompressInit(&stream, 0, 0) != BZ_OK) throw std::bad_alloc();
  stream.next_in = const_cast<char*>(reinterpret_cast<const char*>(data));
  stream.avail_in = static_cast<unsigned int>(size);
  Output out(out_size);
  int status = BZ_OK;
  while (status == BZ_OK) {
    out.Grow();  // At the stated size the stream may still have its end to read.
    const unsigned int room = static_cast<unsigned int>(std::min<size_t>(out.room(), UINT_MAX));
    const unsigned int in_before = stream.avail_in;
    stream.next_out = reinterpret_cast<char*>(out.next());
    stream.avail_out = room;
    status = BZ2_bzDecompress(&stream);
    out.Produced(room - stream.avail_out);
    if (status == BZ_OK && stream.avail_out == room && stream.avail_in == in_before) status = BZ_UNEXPECTED_EOF;
  }
  BZ2_bzDecompressEnd(&stream);
  if (status != BZ_STREAM_END || out.used() != out_size) {
    throw InputError(where + ": the bz2 chunk does not decompress" +
                     (status == BZ_STREAM_END || status == BZ_OK ? " to its stated size"
                                                                 : " (bzip2 error " + std::to_string(status) + ")"));
  }
  return out.Take();
}

std::vector<uint8_t> Lz4(const uint8_t* data, size_t size, size_t out_size, const std::string& where) {
  LZ4F_dctx* context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION))) throw std::bad_alloc();
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> owner(context,
                                                                                    LZ4F_freeDecompressionContext);
  Output out(out_size);
  size_t in_pos = 0, hint = 1;
  while (hint != 0) {
    out.Grow();  // At the stated size the frame may still have its end mark and checksum to read.
    size_t in_left = size - in_pos, out_left = out.room();
    hint = LZ4F_decompress(context, out.next(), &out_left, data + in_pos, &in_left, nullptr);
    if (LZ4F_isError(hint)) {
      throw InputError(where + ": the lz4 chunk does not decompress (" + LZ4F_getErrorName(hint) + ")");
    }
    in_pos += in_left;
    out.Produced(out_left);
    if (hint != 0 && in_left == 0 && out_left == 0) {
      throw InputError(where + (in_pos == size ? ": the lz4 chunk ends early"
                                               : ": the lz4 chunk decompresses to more than its stated size"));
    }
  }
  if (out.used() != out_size) throw InputError(where + ": the lz4 chunk does not decompress to its stated size");
  return out.Take();
}

std::vector<uint8_t> Zstd(const uint8_t* data, size_t size, size_t out_size, const std::string& where) {
  const std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> context(ZSTD_createDCtx(), ZSTD_freeDCtx);
  if (!context) throw std::bad_alloc();
  Output out(out_size);
  ZSTD_inBuffer in{data, size, 0};
  size_t left = 1;  // 0 once the frame is complete.
  while (left != 0) {
    out.Grow();  // At the stated size the frame may still have its checksum to read.
    const size_t in_before = in.pos;
    ZSTD_outBuffer buffer{out.next(), out.room(), 0};
    left = ZSTD_decompressStream(context.get(), &buffer, &in);
    if (ZSTD_isError(left)) {
      throw InputError(where + ": the zstd chunk does not decompress (" + ZSTD_getErrorName(left) + ")");
    }
    out.Produced(buffer.pos);
    if (left != 0 && buffer.pos == 0 && in.pos == in_before) {
      throw InputError(where + (in.pos == in.size ? ": the zstd chunk ends early"
                                                  : ": the zstd chunk decompresses to more than its stated size"));
    }
  }
  if (out.used() != out_size) throw InputError(where + ": the zstd chunk does not decompress to its stated size");
  return out.Take();
}

}  // namespace

std::vector<uint8_t> Decompress(const std::string& name, const uint8_t* data, size_t size, size_t uncompressed_size,
                                const std::string& where) {
  if (uncompressed_size > kMaxChunkBytes) {
    throw InputError(where + ": a chunk of " + std::to_string(uncompressed_size) + " bytes (over 1 GiB: damaged?)");
  }
  if (uncompressed_size == 0) return {};
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
