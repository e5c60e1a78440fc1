// SPDX-License-Identifier: MIT
// What the fuzz targets share. Each target feeds its input to the readers a user's files go
// through, as they go through them: written to a file of a small, otherwise valid dataset layout,
// then opened. Only InputError (a clear message naming the file) may come out; any other exception,
// a crash, a sanitizer report, or an accepted result that breaks the readers' promises is a bug.
//
// Input layout: the first byte chooses which file of the target's layout the rest replaces
// (byte % files; the seeds use the digits '0', '1', ... so '0' picks the first file), and one
// newline right after it is skipped, so that a seed is "1\n<the file's text>".
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/geometry/trajectory.h"
#include "dsm/io/dataset.h"

namespace dsm::fuzz {

struct Choice {
  size_t file = 0;        // Index into the target's file list.
  std::string_view text;  // The bytes that replace it.
};
Choice Split(const uint8_t* data, size_t size, size_t files);

// With DSM_FUZZ_VERBOSE set, prints what became of an input (the replay programs' way to show why
// a seed is rejected).
void Report(const std::string& outcome);

// A folder of this process's own, made on first use and removed when the process exits.
const std::filesystem::path& Scratch();

// Writes `bytes` to `path` (making its folder); aborts when it cannot (the fuzzer's own fault).
void WriteFile(const std::filesystem::path& path, std::string_view bytes);

// A small grey PNG of `width` x `height` at `path`.
void WritePng(const std::filesystem::path& path, int width, int height);

// A layout of valid files under one root; Apply writes one file's fuzzed text, Restore puts the
// valid text back so that the next input starts from the valid layout again.
class Layout {
 public:
  struct File {
    std::string path;     // Relative to the root.
    std::string valid;    // Its valid contents.
    std::string dataset;  // The dataset folder it belongs to, relative to the root.
  };
  Layout(std::filesystem::path root, std::vector<File> files);
  size_t size() const { return files_.size(); }
  const std::filesystem::path& root() const { return root_; }
  void Apply(const Choice& choice) const;
  void Restore(const Choice& choice) const;
  std::filesystem::path Dataset(const Choice& choice) const { return root_ / files_[choice.file].dataset; }

 private:
  std::filesystem::path root_;
  std::vector<File> files_;
};

// The promises of the readers, checked on whatever they accept (aborting with a message when one
// is broken): a calibration that passed Validate; frames non-empty with strictly increasing
// stamps; finite poses with unit rotations; an undistorter that can be built for a camera of at
// most 0.5 Mpixel (larger ones are skipped for speed), or a clear InputError from it.
void CheckTrajectory(const Trajectory& trajectory);
void CheckDataset(const Dataset& dataset);

// One input of a dataset target: writes the chosen file, opens its dataset as `dsm info` does,
// checks what is accepted, and restores the valid layout.
void FuzzDataset(const Layout& layout, const uint8_t* data, size_t size);

}  // namespace dsm::fuzz
