// SPDX-License-Identifier: MIT
// Point clouds as binary little-endian PLY (the Stanford polygon format; Open3D, MeshLab and
// CloudCompare read it): one "vertex" element with float x y z, optionally uchar red green blue,
// then named int columns.
//
//   ply
//   format binary_little_endian 1.0
//   comment ...
//   element vertex N
//   property float x | y | z
//   property uchar red | green | blue      (when colours are given)
//   property int NAME                      (one per column)
//   end_header
//   N rows of 12 [+ 3] + 4 * columns bytes
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace dsm {

struct PlyCloud {
  std::vector<Eigen::Vector3f> xyz;
  std::vector<std::array<uint8_t, 3>> rgb;  // Empty, or one per vertex.
  // Named int columns (PLY names: letters, digits, '_'), one value per vertex each.
  std::vector<std::pair<std::string, std::vector<int32_t>>> ints;
  std::vector<std::string> comments;  // One line each, no newlines.
};

// Throws InputError naming the file when it cannot be written; DSM_CHECK on inconsistent columns.
void WritePly(const std::filesystem::path& path, const PlyCloud& cloud);

// Reads a file of the layout above (as WritePly writes it: float x y z, optional uchar red green
// blue, int columns, one vertex element). Throws InputError naming the file for anything else.
PlyCloud ReadPly(const std::filesystem::path& path);

}  // namespace dsm
