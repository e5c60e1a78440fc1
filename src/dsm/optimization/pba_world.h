// SPDX-License-Identifier: MIT
// A small bundle-adjustment problem on rendered frames with exact poses and depths, for the PBA's
// tests and benchmark.
#pragma once

#include <vector>

#include "dsm/map/map.h"
#include "dsm/synth/scenes.h"

namespace dsm::testing {

struct World {
  synth::SynthSequence seq;
  Map map;
  std::vector<SE3d> true_cam_from_world;
};

// Keyframes at `frames` of the `shake` scene (true poses), points at high-gradient pixels (every
// `stride` px) of the first two with their true depth, observed in every other keyframe.
void BuildWorld(const std::vector<int>& frames, World* w, int stride = 6, double blur_px = 0.0, int width = 320,
                int height = 240);

// Perturbs keyframe poses (~1 cm, ~0.35 deg, times `scale`), brightness and depths (5%),
// deterministically. Keyframe 0 keeps its pose.
void Perturb(World* w, double scale = 1.0);

}  // namespace dsm::testing
