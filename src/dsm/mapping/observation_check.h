// SPDX-License-Identifier: MIT
// Does a map point look like itself in a keyframe, at the current poses? Its 8-pixel pattern is
// compared at level 0 (photometric residual, residual.h) and each pixel tested against the
// keyframe's error model: the point is inconsistent there when more than `max_bad_ratio` of the
// pixels are clearly outliers (|sqrt(w_g) r| above the model's outlier threshold: the poses are
// not refined yet, so only what is more likely an outlier counts), or when the pattern leaves the
// image. A point hidden behind a nearer surface fails this test even when no map point
// lies on that surface yet (a new occluder). Used before the bundle adjustment has judged a new
// keyframe's observations, e.g. so that hidden points do not keep new points from being
// activated where the image now shows something else.
#pragma once

#include "dsm/geometry/camera.h"
#include "dsm/map/map.h"
#include "dsm/photometric/robust.h"
#include "dsm/photometric/texture_loss.h"

namespace dsm {

bool LooksConsistent(const Map& map, const PinholeCamera& camera, const Point& point, int target,
                     const ErrorModel& model, double max_bad_ratio);

// Has the point's texture vanished in the keyframe at the current poses (TextureLost at level 0)?
// False when the pattern leaves the image or the test is not made (texture_loss.h).
bool TextureGone(const Map& map, const PinholeCamera& camera, const Point& point, int target,
                 const TextureLossOptions& options);

}  // namespace dsm
