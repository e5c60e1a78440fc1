// SPDX-License-Identifier: MIT
// The cubic ease 3t^2 - 2t^3 (C1: zero slope at t = 0 and 1) that the textures and the camera
// paths blend with.
#pragma once

#include <algorithm>

namespace dsm::synth {

template <typename T>
inline T Fade(T t) {
  return t * t * (T(3) - T(2) * t);
}

// 0 for x <= e0, 1 for x >= e1, Fade between.
template <typename T>
inline T SmoothStep(T e0, T e1, T x) {
  return Fade(std::clamp((x - e0) / (e1 - e0), T(0), T(1)));
}

}  // namespace dsm::synth
