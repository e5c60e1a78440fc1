// SPDX-License-Identifier: MIT
// Text parsing shared by the file readers. Every function that can fail on user data throws
// InputError with a message naming `where` (a file and line, or an option).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace dsm {

// Splits on any of `separators`, skipping empty fields.
std::vector<std::string> SplitFields(std::string_view line, std::string_view separators = " \t,");

std::string_view Trim(std::string_view s);

// Parses a full field as a finite double / integer; throws InputError naming `where`.
double ParseDouble(std::string_view field, const std::string& where);
int64_t ParseInt(std::string_view field, const std::string& where);

// Parses a timestamp given in `unit_ns` units (1 for nanoseconds, 1e9 for seconds) into exact
// integer nanoseconds. Plain decimals are converted digit by digit, so "1403636584.763555584"
// (seconds) and "1403636584763555584" (ns) are exact; scientific notation goes through long double.
int64_t ParseTimestampNs(std::string_view field, int64_t unit_ns, const std::string& where);

// Formats nanoseconds as seconds with all nine decimals ("1403636584.763555584").
std::string FormatSeconds(int64_t t_ns);

// Reads a whole text file as lines (without line ends); throws InputError if it cannot be read.
std::vector<std::string> ReadLines(const std::filesystem::path& path);

// The data rows of a text file: lines that are not empty and do not start with '#' or '%',
// split into fields; `line` is the 0-based line index for messages.
struct DataRow {
  size_t line = 0;
  std::vector<std::string> fields;
};
std::vector<DataRow> ReadDataRows(const std::filesystem::path& path, std::string_view separators = " \t");

// "file:line" for messages.
std::string Where(const std::filesystem::path& path, size_t line_index);

}  // namespace dsm
