// SPDX-License-Identifier: MIT
// Map files (`dsm run --load-map`, `dsm map info`): the input is the whole file. An accepted file
// must describe itself, hold maps whose ids and hosts are in range, and be written again to a file
// that reads back to the same bytes when written once more (the reader and writer agree).
#include <fstream>
#include <iterator>
#include <string>

#include "dsm/mapfile/map_file.h"
#include "dsm/util/check.h"
#include "fuzz/fuzz_input.h"

namespace {

std::string Bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = dsm::fuzz::Scratch() / "input.dsmmap";
  dsm::fuzz::WriteFile(path, std::string_view(reinterpret_cast<const char*>(data), size));
  try {
    const dsm::MapFile file = dsm::ReadMapFile(path);
    DSM_CHECK(!dsm::DescribeMapFile(path, file).empty(), "an accepted map file describes itself");
    for (const dsm::StoredMap& m : file.maps) {
      for (int id = 0; id < m.map.NumPoints(); ++id) {
        const dsm::Point& p = m.map.point(id);
        DSM_CHECK(p.host >= 0 && p.host < m.map.NumKeyframes(), "a point's host is in its map");
        for (const dsm::Observation& o : p.observations)
          DSM_CHECK(o.target >= 0 && o.target < m.map.NumKeyframes(), "an observation's target is in its map");
      }
    }
    const std::filesystem::path again = dsm::fuzz::Scratch() / "again.dsmmap";
    const std::filesystem::path twice = dsm::fuzz::Scratch() / "twice.dsmmap";
    dsm::WriteMapFile(again, file);
    dsm::WriteMapFile(twice, dsm::ReadMapFile(again));
    DSM_CHECK(Bytes(again) == Bytes(twice), "a map file written, read and written again is the same file");
    dsm::fuzz::Report("accepted");
  } catch (const dsm::InputError& e) {
    dsm::fuzz::Report(std::string("rejected: ") + e.what());
  }
  return 0;
}
