// SPDX-License-Identifier: MIT
// Map files (`dsm run --save-map`): every map of a run, with all a later run needs to track, map
// and relocalise in them, in one zip archive (zip_archive.h) of a JSON manifest and raw arrays.
//
// Format version 1. Entries:
//   manifest.json   {"format": "dsm-map", "version": 1, "created_by": "dsm <version>",
//                    "camera": {width, height, fx, fy, cx, cy}  (the undistorted pinhole camera),
//                    "options": the option file of the run that made the maps (config/option_registry.h),
//                    "maps": [{"id", "keyframes", "points", "observations", "thumbnail_values",
//                              "covisibility_links", "interpolation": "bilinear" | "bspline",
//                              "window": [ids], "covisible": [ids], "image_noise_sigma",
//                              "tracking_levels": {"residual", "texture"}}, ...],
//                    "arrays": {"<entry name>": {"type", "shape", "crc32"}, ...}}
//   maps/<i>/<array> one raw array per entry, little-endian, row-major, of the type and shape the
//                    manifest gives (types u8, u16, i32, i64, f32, f64), for the map at position i:
//     keyframe_time          i64 [K, 2]   input frame index, timestamp (ns)
//     keyframe_pose          f64 [K, 7]   cam_from_world: quaternion x y z w, translation x y z
//     keyframe_brightness    f64 [K, 3]   affine a, b (photometric/residual.h), exposure
//     keyframe_error_model   f64 [K, 6]   kind (robust.h RobustKind), nu, sigma, huber_k,
//                                         inlier_threshold, fitted (0 | 1)
//     keyframe_levels        i32 [K, 2]   pyramid levels, most_pba_links (map.h)
//     keyframe_image         u16 [K, H, W] level 0 in fixed point (ImagePyramid::kValueScale)
//     keyframe_signature     f64 [K, 3]   texture, mean, deviation (image/signature.h)
//     keyframe_thumbnail_size i32 [K, 2]  thumbnail width, height (0 x 0: a uniform image) ...
//     keyframe_thumbnail     f32 [T]      ... the thumbnails, one after the other
//     keyframe_covisibility_offsets i32 [K + 1] ... the covisible keyframes of the window each was
//     keyframe_covisibility  i32 [C]              mapped in (offsets into this list)
//     point_host             i32 [P]      host keyframe (points in id order)
//     point_pixel            f32 [P, 2]   level-0 pixel in the host
//     point_idepth           f32 [P]      inverse depth in the host camera
//     point_created          i32 [P]      keyframes in the map when it was activated
//     point_flags            u8  [P]      1: removed, 2: patch sampled, 4: patch by the B-spline
//     point_patch            f32 [P, 18]  host patch: centre x y, 8 values, 8 gradient weights
//     observation_offsets    i32 [P + 1]  each point's observations, in order, in ...
//     observation_target     i32 [O]      ... target keyframe
//     observation_outlier    u8  [O]      ... 1: an outlier
// A keyframe's hosted points follow from point_host. The zip's CRC-32 guards each entry and the
// manifest's crc32 (zlib's) each array; the reader checks both, every size against the manifest
// and every id, pixel, depth and pose before it builds a map.
//
// Errors (InputError naming the file): not a zip, no manifest, another format, a version this
// build does not read, an array missing, of another type or shape, damaged (CRC) or truncated,
// values out of range (ids, non-finite poses or depths, pixels outside the image).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/map/stored_map.h"

namespace dsm {

inline constexpr int kMapFileVersion = 1;

struct MapFile {
  std::string created_by;  // "dsm <version>" of the build that wrote it.
  PinholeCamera camera;    // The undistorted camera the maps were made with.
  std::string options;     // The option file (YAML) of the run that made them.
  std::vector<StoredMap> maps;
};

// Writes `file` to `path` (replacing it only when the whole file is written); throws InputError
// naming the path when it cannot be written.
void WriteMapFile(const std::filesystem::path& path, const MapFile& file);
// Reads a map file; throws InputError naming the path (see above) when it is not a valid one.
MapFile ReadMapFile(const std::filesystem::path& path);

// The maps of `file` (read from `path`) that a run with the undistorted `camera` takes up: those
// with keyframes, in order. InputError naming `path` when the file was made with another camera
// (another size, or intrinsics that differ by more than 1e-6 relative) or holds no such map.
std::vector<StoredMap> MapsToTakeUp(const std::filesystem::path& path, MapFile file, const PinholeCamera& camera);

// "WxH pinhole, fx .. fy .. cx .. cy ..", as messages and `dsm map info` name a camera.
std::string CameraText(const PinholeCamera& camera);

// `dsm map info`: format, version, creator, camera, and per map its keyframes, live points,
// observations, the keyframes' frame range and the box around the live points (world).
std::string DescribeMapFile(const std::filesystem::path& path, const MapFile& file);

}  // namespace dsm
