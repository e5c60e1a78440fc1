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

PlyCloud ReadPly(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open the PLY file");
  const auto fail = [&](const std::string& why) { return InputError(path.string() + ": " + why); };
  std::string line;
  if (!std::getline(in, line) || line != "ply") throw fail("not a PLY file");
  if (!std::getline(in, line) || line != "format binary_little_endian 1.0") throw fail("not binary little-endian PLY");
  PlyCloud cloud;
  long long count = -1;
  std::vector<std::string> floats, uchars;
  std::vector<std::string> ints;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string keyword, type, name;
    words >> keyword;
    if (keyword == "comment") {
      cloud.comments.push_back(line.size() > 8 ? line.substr(8) : "");
    } else if (keyword == "element") {
      words >> name >> count;
      if (name != "vertex" || !words || count < 0 || count > (1LL << 31)) throw fail("unexpected element '" + line + "'");
    } else if (keyword == "property" && words >> type >> name) {
      if (type == "float" && ints.empty() && uchars.empty()) {
        floats.push_back(name);
      } else if (type == "uchar" && ints.empty()) {
        uchars.push_back(name);
      } else if (type == "int") {
        ints.push_back(name);
      } else {
        throw fail("unexpected property '" + line + "'");
      }
    } else {
      throw fail("unexpected header line '" + line + "'");
    }
  }
  if (line != "end_header" || count < 0) throw fail("incomplete header");
  if (floats != std::vector<std::string>{"x", "y", "z"}) throw fail("expected float x y z first");
  if (!uchars.empty() && uchars != std::vector<std::string>{"red", "green", "blue"}) throw fail("expected uchar red green blue");
  const size_t n = static_cast<size_t>(count);
  const size_t row_bytes = 12 + uchars.size() + 4 * ints.size();
  std::vector<char> body(n * row_bytes);
  if (!in.read(body.data(), static_cast<std::streamsize>(body.size()))) throw fail("file ends inside the vertex rows");
  cloud.xyz.resize(n);
  if (!uchars.empty()) cloud.rgb.resize(n);
  for (const std::string& name : ints) cloud.ints.push_back({name, std::vector<int32_t>(n)});
  const char* row = body.data();
  for (size_t i = 0; i < n; ++i, row += row_bytes) {
    std::memcpy(cloud.xyz[i].data(), row, 12);
    size_t at = 12;
    if (!uchars.empty()) {
      std::memcpy(cloud.rgb[i].data(), row + at, 3);
      at += 3;
    }
    for (auto& column : cloud.ints) {
      std::memcpy(&column.second[i], row + at, 4);
      at += 4;
    }
  }
  return cloud;
}

}  // namespace dsm
