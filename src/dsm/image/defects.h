// SPDX-License-Identifier: MIT
// Defects injected into a recording (`dsm synth --defects`, `dsm damage`), the bad frames a live
// system meets: a spec is a comma-separated list of KIND:FIRST[-LAST] (frame indices, inclusive),
// e.g.
//   black:200-214,noise:300-314,corrupt:350,cover:400-440
// Image defects replace or spoil the frame:
//   black      all 0 (lens cap, light off)        saturated  all 255 (blinded)
//   noise      uniform random grey levels         cover      a hand over the lens: the view fades
//                                                            under a dark, smooth, defocused shape
// File defects damage the written file: corrupt (bytes flipped in the middle: the PNG's CRC
// fails), truncated (cut at half its size), empty (zero bytes). Ground truth keeps every frame.
// cut leaves the frames out of the recording: the camera reappears where it went meanwhile, the
// frames after keep their timestamps, and the images (and ground truth) are numbered in order
// without them. Every index in a spec is a rendered frame's (before the cut).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dsm/image/image.h"

namespace dsm {

enum class DefectKind { kBlack, kSaturated, kNoise, kCover, kCorrupt, kTruncated, kEmpty, kCut };

struct Defect {
  DefectKind kind = DefectKind::kBlack;
  int first = 0, last = 0;
};

bool IsFileDefect(DefectKind kind);  // corrupt, truncated, empty
// The first defect of `frame` among the file defects (file) or the others, or nullptr.
const Defect* FindDefect(const std::vector<Defect>& defects, int frame, bool file);
// True when a cut leaves rendered frame `frame` out.
bool IsCut(const std::vector<Defect>& defects, int frame);

// Parses a spec; throws InputError naming the item that is wrong. Empty spec: no defects.
std::vector<Defect> ParseDefects(const std::string& spec);

// The image defect of `frame` applied to its image (unchanged when there is none). Deterministic
// in (seed, frame).
void ApplyImageDefects(const std::vector<Defect>& defects, int frame, uint32_t seed, Image<uint8_t>* image);

// The file defect of `frame` applied to its written file, if any.
void ApplyFileDefects(const std::vector<Defect>& defects, int frame, const std::filesystem::path& file);

}  // namespace dsm
