// SPDX-License-Identifier: MIT
#include "dsm/io/ply.h"

#include <bit>
#include <cctype>
#include <cstring>
#include <fstream>
#include <sstream>

#include "dsm/util/check.h"

namespace dsm {

static_assert(std::endian::native == std::endian::little, "PLY rows are written as the machine stores them");

namespace {

bool IsPlyName(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

template <typename T>
void Put(std::vector<char>* row, size_t* at, T value) {
  std::memcpy(row->data() + *at, &value, sizeof(T));
  *at += sizeof(T);
}

}  // namespace

void WritePly(const std::filesystem::path& path, const PlyCloud& cloud) {
  const size_t n = cloud.xyz.size();
  const bool colour = !cloud.rgb.empty();
  DSM_CHECK(!colour || cloud.rgb.size() == n, "PLY colours: one per vertex");
  for (const auto& [name, values] : cloud.ints) {
    DSM_CHECK(IsPlyName(name), "PLY property name '" + name + "'");
    DSM_CHECK(values.size() == n, "PLY column '" + name + "': one value per vertex");
  }
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\n";
  for (const std::string& c : cloud.comments) {
    DSM_CHECK(c.find('\n') == std::string::npos, "PLY comment with a newline");
    header << "comment " << c << "\n";
  }
  header << "element vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (colour) header << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  for (const auto& column : cloud.ints) header << "property int " << column.first << "\n";
  header << "end_header\n";

  const size_t row_bytes = 3 * sizeof(float) + (colour ? 3 : 0) + cloud.ints.size() * sizeof(int32_t);
  std::vector<char> body(n * row_bytes);
  size_t at = 0;
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) Put(&body, &at, cloud.xyz[i][k]);
    if (colour)
      for (uint8_t c : cloud.rgb[i]) Put(&body, &at, c);
    for (const auto& column : cloud.ints) Put(&body, &at, column.second[i]);
  }
  std::ofstream out(path, std::ios::binary);
  const std::string text = header.str();
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.write(body.data(), static_cast<std::streamsize>(body.size()));
  if (!out) throw InputError(path.string() + ": cannot write file");
}

}  // namespace dsm
