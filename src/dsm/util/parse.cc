// SPDX-License-Identifier: MIT
#include "dsm/util/parse.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>

#include "dsm/util/check.h"

namespace dsm {

std::vector<std::string> SplitFields(std::string_view line, std::string_view separators) {
  std::vector<std::string> fields;
  size_t start = 0;
  while (start <= line.size()) {
    const size_t end = line.find_first_of(separators, start);
    const size_t stop = end == std::string_view::npos ? line.size() : end;
    if (stop > start) fields.emplace_back(line.substr(start, stop - start));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return fields;
}

std::string_view Trim(std::string_view s) {
  const size_t begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string_view::npos) return {};
  const size_t end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

double ParseDouble(std::string_view field, const std::string& where) {
  const std::string_view s = Trim(field);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(value)) {
    throw InputError(where + ": expected a number, found '" + std::string(field) + "'");
  }
  return value;
}

int64_t ParseInt(std::string_view field, const std::string& where) {
  const std::string_view s = Trim(field);
  int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) {
    throw InputError(where + ": expected an integer, found '" + std::string(field) + "'");
  }
  return value;
}

int64_t ParseTimestampNs(std::string_view field, int64_t unit_ns, const std::string& where) {
  const std::string_view s = Trim(field);
  const auto fail = [&]() -> int64_t {
    throw InputError(where + ": expected a timestamp, found '" + std::string(field) + "'");
  };
  if (s.empty()) return fail();
  if (s.find_first_of("eE") != std::string_view::npos) {
    long double value = 0.0L;
    try {
      size_t used = 0;
      value = std::stold(std::string(s), &used);
      if (used != s.size()) return fail();
    } catch (const std::exception&) {
      return fail();
    }
    const long double ns = value * static_cast<long double>(unit_ns);
    if (!std::isfinite(ns) || std::fabs(ns) > 9.0e18L) return fail();
    return static_cast<int64_t>(std::llround(ns));
  }
  // Exact decimal: integer part times unit, plus the fraction digit by digit.
  const bool negative = s.front() == '-';
  const std::string_view body = negative ? s.substr(1) : s;
  const size_t dot = body.find('.');
  const std::string_view int_part = body.substr(0, dot);
  const std::string_view frac_part = dot == std::string_view::npos ? "" : body.substr(dot + 1);
  if (int_part.empty() && frac_part.empty()) return fail();
  for (char c : int_part) if (c < '0' || c > '9') return fail();
  for (char c : frac_part) if (c < '0' || c > '9') return fail();
  int64_t whole = 0;
  if (!int_part.empty()) {
    const auto [ptr, ec] = std::from_chars(int_part.data(), int_part.data() + int_part.size(), whole);
    if (ec != std::errc() || ptr != int_part.data() + int_part.size()) return fail();
  }
  // Fraction: digits scaled by unit/10, unit/100, ...; digits below 1 ns are rounded (so 0 <= frac <= unit).
  int64_t frac = 0;
  int64_t scale = unit_ns;
  for (size_t i = 0; i < frac_part.size(); ++i) {
    const int digit = frac_part[i] - '0';
    if (scale >= 10) {
      scale /= 10;
      frac += digit * scale;
    } else {
      if (digit >= 5) frac += 1;
      break;
    }
  }
  // whole * unit + frac must fit: whole <= (max - frac) / unit.
  if (whole > (std::numeric_limits<int64_t>::max() - frac) / unit_ns) return fail();
  const int64_t ns = whole * unit_ns + frac;
  return negative ? -ns : ns;
}

std::string FormatSeconds(int64_t t_ns) {
  const bool negative = t_ns < 0;
  const uint64_t abs_ns = negative ? static_cast<uint64_t>(-(t_ns + 1)) + 1 : static_cast<uint64_t>(t_ns);
  char buffer[48];
  std::snprintf(buffer, sizeof(buffer), "%s%llu.%09llu", negative ? "-" : "",
                static_cast<unsigned long long>(abs_ns / 1000000000ULL),
                static_cast<unsigned long long>(abs_ns % 1000000000ULL));
  return buffer;
}

std::vector<std::string> ReadLines(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open file");
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
  }
  if (in.bad()) throw InputError(path.string() + ": read error");
  return lines;
}

std::vector<DataRow> ReadDataRows(const std::filesystem::path& path, std::string_view separators) {
  std::vector<DataRow> rows;
  const auto lines = ReadLines(path);
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string_view t = Trim(lines[i]);
    if (t.empty() || t.front() == '#' || t.front() == '%') continue;
    rows.push_back({i, SplitFields(t, separators)});
  }
  return rows;
}

std::string Where(const std::filesystem::path& path, size_t line_index) {
  return path.string() + ":" + std::to_string(line_index + 1);
}

}  // namespace dsm
