// SPDX-License-Identifier: MIT
#include "fuzz/fuzz_input.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "dsm/geometry/undistorter.h"
#include "dsm/image/image.h"
#include "dsm/io/image_io.h"
#include "dsm/util/check.h"

namespace dsm::fuzz {

namespace fs = std::filesystem;

void Report(const std::string& outcome) {
  static const bool verbose = std::getenv("DSM_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "%s\n", outcome.c_str());
}

Choice Split(const uint8_t* data, size_t size, size_t files) {
  Choice c;
  if (size == 0) return c;
  c.file = static_cast<uint8_t>(data[0] - '0') % files;
  size_t skip = 1;
  if (size > 1 && data[1] == '\n') skip = 2;
  c.text = std::string_view(reinterpret_cast<const char*>(data) + skip, size - skip);
  return c;
}

namespace {

struct ScratchFolder {
  fs::path path;
  ScratchFolder() {
    std::string pattern = (fs::temp_directory_path() / "dsm-fuzz-XXXXXX").string();
    DSM_CHECK(::mkdtemp(pattern.data()) != nullptr, "cannot make a scratch folder under " + pattern);
    path = pattern;
  }
  ~ScratchFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

}  // namespace

const fs::path& Scratch() {
  static const ScratchFolder folder;
  return folder.path;
}

void WriteFile(const fs::path& path, std::string_view bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  DSM_CHECK(out.good(), "cannot write " + path.string());
}

void WritePng(const fs::path& path, int width, int height) {
  fs::create_directories(path.parent_path());
  Image<uint8_t> image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image(x, y) = static_cast<uint8_t>((x * 7 + y * 13) & 0xff);
  WriteGray8(path, image);
}

Layout::Layout(fs::path root, std::vector<File> files) : root_(std::move(root)), files_(std::move(files)) {
  for (const File& f : files_) WriteFile(root_ / f.path, f.valid);
}

void Layout::Apply(const Choice& choice) const { WriteFile(root_ / files_[choice.file].path, choice.text); }

void Layout::Restore(const Choice& choice) const {
  WriteFile(root_ / files_[choice.file].path, files_[choice.file].valid);
}

void CheckTrajectory(const Trajectory& trajectory) {
  DSM_CHECK(!trajectory.empty(), "a reader accepted a trajectory without poses");
  DSM_CHECK(!trajectory.HasStamps() || trajectory.stamps_ns.size() == trajectory.poses.size(),
            "stamps and poses differ in number");
  for (const SE3d& pose : trajectory.poses) {
    DSM_CHECK(pose.Translation().allFinite(), "a reader accepted a pose with a non-finite position");
    DSM_CHECK(std::abs(pose.So3().Quaternion().norm() - 1.0) < 1e-9, "a reader accepted a non-unit rotation");
  }
}

void CheckDataset(const Dataset& dataset) {
  try {
    dataset.camera.Validate("accepted calibration");
  } catch (const InputError& e) {
    DSM_CHECK(false, std::string("a reader accepted a calibration that fails Validate: ") + e.what());
  }
  DSM_CHECK(!dataset.frames.empty(), "a reader accepted a dataset without frames");
  for (size_t i = 1; i < dataset.frames.size(); ++i)
    DSM_CHECK(dataset.frames[i].t_ns > dataset.frames[i - 1].t_ns, "a reader accepted non-increasing stamps");
  for (const FrameRecord& f : dataset.frames)
    DSM_CHECK(std::isfinite(f.exposure_ms) && f.exposure_ms >= 0.0, "a reader accepted a bad exposure time");
  if (dataset.HasGroundTruth()) CheckTrajectory(dataset.ground_truth);
  DSM_CHECK(dataset.images != nullptr, "a reader accepted a dataset without an image store");
  // What `dsm info` and the start of `dsm run` do next, for cameras of at most 0.5 Mpx (speed).
  if (static_cast<int64_t>(dataset.camera.width) * dataset.camera.height > 500000) return;
  try {
    // As `dsm info` builds it (5 pyramid levels: sizes a multiple of 16).
    const Undistorter undistorter(dataset.camera, {dataset.undistort_mode, 16});
    const PinholeCamera& out = undistorter.output();
    DSM_CHECK(out.width > 0 && out.height > 0 && std::isfinite(out.fx) && std::isfinite(out.fy) && out.fx > 0 &&
                  out.fy > 0 && std::isfinite(out.cx) && std::isfinite(out.cy),
              "the undistorter made an implausible output camera");
    DSM_CHECK(!DescribeDataset(dataset, undistorter).empty(), "empty description");
  } catch (const InputError&) {
  }
  try {
    dataset.LoadImage(0);
  } catch (const InputError&) {
  }
}

void FuzzDataset(const Layout& layout, const uint8_t* data, size_t size) {
  const Choice choice = Split(data, size, layout.size());
  layout.Apply(choice);
  try {
    CheckDataset(OpenDataset(layout.Dataset(choice)));
    Report("accepted");
  } catch (const InputError& e) {
    Report(std::string("rejected: ") + e.what());
  }
  layout.Restore(choice);
}

}  // namespace dsm::fuzz
