// SPDX-License-Identifier: MIT
#include "dsm/image/defects.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>

#include "dsm/util/check.h"
#include "dsm/util/parse.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

struct KindName {
  DefectKind kind;
  const char* name;
};
constexpr KindName kKinds[] = {{DefectKind::kBlack, "black"},     {DefectKind::kSaturated, "saturated"},
                               {DefectKind::kNoise, "noise"},     {DefectKind::kCover, "cover"},
                               {DefectKind::kCorrupt, "corrupt"}, {DefectKind::kTruncated, "truncated"},
                               {DefectKind::kEmpty, "empty"},     {DefectKind::kCut, "cut"}};

int ParseFrame(const std::string& text, const std::string& item) {
  const int64_t v = ParseInt(text, "--defects: '" + item + "'");
  if (v < 0 || v > 1000000) throw InputError("--defects: '" + item + "': frame '" + text + "' is not a frame index");
  return static_cast<int>(v);
}

}  // namespace

bool IsFileDefect(DefectKind k) {
  return k == DefectKind::kCorrupt || k == DefectKind::kTruncated || k == DefectKind::kEmpty;
}

const Defect* FindDefect(const std::vector<Defect>& defects, int frame, bool file) {
  for (const Defect& d : defects)
    if (frame >= d.first && frame <= d.last && IsFileDefect(d.kind) == file) return &d;
  return nullptr;
}

bool IsCut(const std::vector<Defect>& defects, int frame) {
  for (const Defect& d : defects)
    if (d.kind == DefectKind::kCut && frame >= d.first && frame <= d.last) return true;
  return false;
}

std::vector<Defect> ParseDefects(const std::string& spec) {
  std::vector<Defect> out;
  std::stringstream list(spec);
  std::string item;
  while (std::getline(list, item, ',')) {
    if (item.empty()) continue;
    const size_t colon = item.find(':');
    if (colon == std::string::npos) throw InputError("--defects: '" + item + "' needs KIND:FIRST[-LAST]");
    const std::string kind = item.substr(0, colon), range = item.substr(colon + 1);
    const auto k = std::find_if(std::begin(kKinds), std::end(kKinds), [&](const KindName& n) { return kind == n.name; });
    if (k == std::end(kKinds)) {
      throw InputError("--defects: unknown kind '" + kind +
                       "' (black, saturated, noise, cover, corrupt, truncated, empty or cut)");
    }
    Defect d;
    d.kind = k->kind;
    const size_t dash = range.find('-');
    d.first = ParseFrame(range.substr(0, dash), item);
    d.last = dash == std::string::npos ? d.first : ParseFrame(range.substr(dash + 1), item);
    if (d.last < d.first) throw InputError("--defects: '" + item + "': the range ends before it starts");
    out.push_back(d);
  }
  return out;
}

void ApplyImageDefects(const std::vector<Defect>& defects, int frame, uint32_t seed, Image<uint8_t>* image) {
  const Defect* d = FindDefect(defects, frame, false);
  if (d == nullptr) return;
  const int w = image->width(), h = image->height();
  std::mt19937 rng(seed * 2246822519u + static_cast<uint32_t>(frame) * 3266489917u + 7u);
  switch (d->kind) {
    case DefectKind::kBlack:
      std::fill(image->data(), image->data() + image->size(), uint8_t{0});
      break;
    case DefectKind::kSaturated:
      std::fill(image->data(), image->data() + image->size(), uint8_t{255});
      break;
    case DefectKind::kNoise: {
      std::uniform_int_distribution<int> grey(0, 255);
      for (size_t i = 0; i < image->size(); ++i) image->data()[i] = static_cast<uint8_t>(grey(rng));
      break;
    }
    case DefectKind::kCover: {
      // Over the first and last three frames of the episode the hand slides in and out; in
      // between it covers the view but for a thin band. The hand: dark skin, shaded smoothly
      // (out of focus, no texture), with sensor noise of 1.5 grey levels.
      const int into = std::min(frame - d->first, d->last - frame);
      const double cover = std::min(1.0, (into + 1) / 4.0);
      std::normal_distribution<float> noise(0.f, 1.5f);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const double edge = cover * 1.1 * w - x;  // The hand enters from the left.
          const double a = std::clamp(edge / (0.08 * w), 0.0, 1.0);
          const double skin = 45.0 + 25.0 * std::exp(-std::pow((x - 0.4 * w) / (0.5 * w), 2) - std::pow((y - 0.5 * h) / (0.6 * h), 2));
          const double v = (1.0 - a) * (*image)(x, y) + a * skin + noise(rng);
          (*image)(x, y) = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
        }
      break;
    }
    default:
      break;
  }
}

void ApplyFileDefects(const std::vector<Defect>& defects, int frame, const fs::path& file) {
  const Defect* d = FindDefect(defects, frame, true);
  if (d == nullptr) return;
  std::vector<char> bytes;
  {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file.string() + ": cannot read the frame to damage");
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  if (d->kind == DefectKind::kEmpty) bytes.clear();
  if (d->kind == DefectKind::kTruncated) bytes.resize(bytes.size() / 2);
  if (d->kind == DefectKind::kCorrupt) {
    // 64 bytes in the middle of the compressed data, as a bad sector or a failed copy leaves them.
    const size_t mid = bytes.size() / 2;
    for (size_t i = mid; i < std::min(bytes.size(), mid + 64); ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0xA5);
  }
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw InputError(file.string() + ": cannot write the damaged frame");
}

}  // namespace dsm
