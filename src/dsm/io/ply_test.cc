// SPDX-License-Identifier: MIT
// PLY files read back by a parser of the format written here, independent of the writer.
#include "dsm/io/ply.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include <gtest/gtest.h>

#include "dsm/util/check.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;

struct ParsedPly {
  std::vector<std::string> header;  // Lines up to and including end_header.
  std::string body;
};

ParsedPly Parse(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t end = bytes.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  ParsedPly ply;
  std::istringstream lines(bytes.substr(0, end + 10));
  for (std::string line; std::getline(lines, line);) ply.header.push_back(line);
  ply.body = bytes.substr(end + 11);
  return ply;
}

template <typename T>
T At(const std::string& body, size_t offset) {
  T value;
  std::memcpy(&value, body.data() + offset, sizeof(T));
  return value;
}

TEST(Ply, HeaderAndRowsAsTheFormatDefines) {
  PlyCloud cloud;
  cloud.xyz = {{1.5f, -2.f, 3.25f}, {0.f, 1e-3f, -7.f}};
  cloud.rgb = {{{10, 20, 30}}, {{255, 0, 128}}};
  cloud.ints = {{"host", {4, 9}}, {"observations", {0, -3}}};
  cloud.comments = {"test cloud"};
  const fs::path path = fs::path(::testing::TempDir()) / "ply_test.ply";
  WritePly(path, cloud);
  const ParsedPly ply = Parse(path);
  const std::vector<std::string> expected = {
      "ply", "format binary_little_endian 1.0", "comment test cloud", "element vertex 2",
      "property float x", "property float y", "property float z", "property uchar red",
      "property uchar green", "property uchar blue", "property int host", "property int observations",
      "end_header"};
  EXPECT_EQ(ply.header, expected);
  constexpr size_t kRow = 12 + 3 + 8;
  ASSERT_EQ(ply.body.size(), 2 * kRow);
  EXPECT_EQ(At<float>(ply.body, 0), 1.5f);
  EXPECT_EQ(At<float>(ply.body, 4), -2.f);
  EXPECT_EQ(At<float>(ply.body, 8), 3.25f);
  EXPECT_EQ(At<uint8_t>(ply.body, 12), 10);
  EXPECT_EQ(At<uint8_t>(ply.body, 14), 30);
  EXPECT_EQ(At<int32_t>(ply.body, 15), 4);
  EXPECT_EQ(At<int32_t>(ply.body, 19), 0);
  EXPECT_EQ(At<float>(ply.body, kRow + 4), 1e-3f);
  EXPECT_EQ(At<uint8_t>(ply.body, kRow + 13), 0);
  EXPECT_EQ(At<int32_t>(ply.body, kRow + 15), 9);
  EXPECT_EQ(At<int32_t>(ply.body, kRow + 19), -3);
}

TEST(Ply, WithoutColoursOrColumns) {
  PlyCloud cloud;
  cloud.xyz = {{1.f, 2.f, 3.f}};
  const fs::path path = fs::path(::testing::TempDir()) / "ply_plain.ply";
  WritePly(path, cloud);
  const ParsedPly ply = Parse(path);
  EXPECT_EQ(ply.header.size(), 7u);
  ASSERT_EQ(ply.body.size(), 12u);
  EXPECT_EQ(At<float>(ply.body, 8), 3.f);
}

TEST(Ply, EmptyCloudIsAValidFile) {
  const fs::path path = fs::path(::testing::TempDir()) / "ply_empty.ply";
  WritePly(path, PlyCloud{});
  const ParsedPly ply = Parse(path);
  EXPECT_EQ(ply.header[2], "element vertex 0");
  EXPECT_TRUE(ply.body.empty());
}

TEST(Ply, UnwritablePathNamesTheFile) {
  PlyCloud cloud;
  cloud.xyz = {{1.f, 2.f, 3.f}};
  const fs::path path = fs::path(::testing::TempDir()) / "no_such_folder" / "map.ply";
  try {
    WritePly(path, cloud);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

TEST(Ply, ReadBackWhatWasWritten) {
  PlyCloud cloud;
  cloud.xyz = {{1.5f, -2.f, 3.25f}, {0.f, 1e-3f, -7.f}};
  cloud.rgb = {{{10, 20, 30}}, {{255, 0, 128}}};
  cloud.ints = {{"host", {4, 9}}};
  const fs::path path = fs::path(::testing::TempDir()) / "ply_round_trip.ply";
  WritePly(path, cloud);
  const PlyCloud back = ReadPly(path);
  EXPECT_EQ(back.xyz, cloud.xyz);
  EXPECT_EQ(back.rgb, cloud.rgb);
  EXPECT_EQ(back.ints, cloud.ints);
}

TEST(Ply, ReadRefusesOtherLayoutsAndCutFiles) {
  const fs::path dir = fs::path(::testing::TempDir());
  const auto error_of = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    try {
      ReadPly(dir / name);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
                             "property float y\nproperty float z\nend_header\n";
  EXPECT_NE(error_of("cut.ply", header + std::string(20, '\0')).find("cut.ply: file ends inside"), std::string::npos);
  EXPECT_NE(error_of("ascii.ply", "ply\nformat ascii 1.0\n").find("not binary little-endian"), std::string::npos);
  EXPECT_NE(error_of("faces.ply", "ply\nformat binary_little_endian 1.0\nelement face 1\n").find("unexpected element"),
            std::string::npos);
  EXPECT_NE(error_of("text.txt", "hello").find("not a PLY file"), std::string::npos);
  EXPECT_EQ(error_of("fine.ply", header + std::string(24, '\0')), "");
}

}  // namespace
}  // namespace dsm
