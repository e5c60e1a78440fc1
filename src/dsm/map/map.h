// SPDX-License-Identifier: MIT
// The persistent map: keyframes with their images and poses, and points with their observations.
// Data only; the algorithms that change it live in optimization/, tracking/ and mapping/.
//
// Poses are stored as cam_from_world (the direction the residuals use); world_from_cam is its
// inverse and is what the outputs report.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "dsm/image/pyramid.h"
#include "dsm/image/signature.h"
#include "dsm/lie/se3.h"
#include "dsm/photometric/residual.h"
#include "dsm/photometric/robust.h"
#include "dsm/util/check.h"

namespace dsm {

struct Observation {
  int target = -1;          // Keyframe id.
  bool outlier = false;     // Removed after a PBA found > 30% outlier pixels.
};

struct Point {
  int id = -1;
  int host = -1;             // Keyframe id.
  Eigen::Vector2f pixel;     // Level-0 pixel in the host.
  float idepth = 1.f;        // Inverse depth in the host camera.
  std::vector<Observation> observations;
  int created_at_keyframe = 0;  // Number of keyframes in the map when it was activated.
  bool removed = false;
  // Its level-0 patch in the host, sampled when it was added (Map::AddPoint), so that checks of
  // old points need no pyramid of their host; patch_ok false: the pattern leaves the image.
  HostPatch patch;
  bool patch_ok = false;

  int NumGoodObservations() const {
    int n = 0;
    for (const Observation& o : observations) n += !o.outlier;
    return n;
  }
  Observation* FindObservation(int target) {
    for (Observation& o : observations)
      if (o.target == target) return &o;
    return nullptr;
  }
  const Observation* FindObservation(int target) const { return const_cast<Point*>(this)->FindObservation(target); }
};

struct Keyframe {
  int id = -1;
  int frame_index = -1;   // Index of the frame in the input sequence.
  int64_t t_ns = 0;
  SE3d cam_from_world;
  AffineBrightness affine;
  double exposure = 1.0;  // Exposure time (1 when unknown).
  // Its image pyramid while the keyframe is in use (Map::LoadPyramids); null once
  // Map::ReleaseUnusedPyramids dropped it. Shared with whoever still reads it (the tracking
  // thread holds its reference keyframe's).
  std::shared_ptr<const ImagePyramid> pyramid;
  // Level-0 intensities in fixed point (ImagePyramid::kValueScale): 2 bytes a pixel instead of
  // the pyramid's ~8, held only while the pyramid is released (the pyramid holds the same values
  // as its level 0). A released pyramid is rebuilt from it, exactly (ImagePyramid::FromFixed).
  // Exactly one of the two is held once the keyframe is in the map: read through Level0() and
  // Intensity().
  Image<uint16_t> image;
  int pyramid_levels = 0;
  int pyramid_used = 0;  // Map epoch of its last use.
  ErrorModel error_model;  // Fitted to the residuals of the observations in this keyframe.
  FrameSignature signature;  // Texture and thumbnail (relocalisation candidates).
  std::vector<int> points; // Ids of the points it hosts.
  // The most observations (hosted or observed) that tied its pose in a bundle adjustment that
  // moved it (pba_selection.h: a later solve with far fewer holds it).
  int most_pba_links = 0;
  // Runtime state, not stored in map files. Frozen: part of a map the run localises in
  // (System::RestoreMap with LoadedMapUse::kLocalize); no adjustment changes its pose, brightness
  // or error model, nor its points' depths or their observations in other frozen keyframes
  // (pba_selection.h). Retired: a keyframe the map no longer uses (Map::Retire); it keeps its
  // pose for the trajectory but no image, points or observations.
  bool frozen = false;
  bool retired = false;

  const ImagePyramid& Pyramid() const {
    DSM_CHECK(pyramid != nullptr, "keyframe pyramid used without Map::LoadPyramids");
    return *pyramid;
  }
  // Its pyramid, or one rebuilt from the fixed-point level 0 for the caller alone when released
  // (the keyframe stays as it is: for readers that may not load pyramids into the map).
  std::shared_ptr<const ImagePyramid> PyramidOrRebuilt() const {
    return pyramid ? pyramid : std::make_shared<const ImagePyramid>(ImagePyramid::FromFixed(image, pyramid_levels));
  }
  float Intensity(int x, int y) const {
    return pyramid != nullptr ? pyramid->Value(0, x, y) : image(x, y) * (1.f / ImagePyramid::kValueScale);
  }
  int width() const { return pyramid != nullptr ? pyramid->width(0) : image.width(); }
  int height() const { return pyramid != nullptr ? pyramid->height(0) : image.height(); }
  Image<uint16_t> Level0() const { return pyramid != nullptr ? pyramid->FixedLevel0() : image; }
  SE3d WorldFromCam() const { return cam_from_world.Inverse(); }
  Eigen::Vector3d Centre() const { return WorldFromCam().Translation(); }
};

class Map {
 public:
  Keyframe& AddKeyframe(std::unique_ptr<Keyframe> keyframe);
  // Adds a point hosted by `point.host`; returns its id.
  int AddPoint(Point point);
  // A map read back as it was saved (mapfile/map_file.h): the keyframe keeps its id (the next one),
  // its fixed-point image and pyramid_levels (its pyramid is rebuilt when used); the point keeps its
  // id (the next one), patch and observations, and joins its host's list. The reader has checked
  // ids, hosts and targets.
  Keyframe& RestoreKeyframe(std::unique_ptr<Keyframe> keyframe);
  void RestorePoint(Point point);

  // Keyframe `id` leaves the map for good (Keyframe::retired): its points are removed, every
  // observation in it is dropped, its pyramid and image are released; its pose stays.
  void Retire(int id);
  // Point `pid` is hosted by keyframe `host` from now on, at `pixel` with `idepth` there (its
  // projection), its patch sampled anew in the host's pyramid (loaded: LoadPyramids); its
  // observation in `host`, if any, goes (the host sees it by definition).
  void Rehost(int pid, int host, const Eigen::Vector2f& pixel, float idepth);
  // Back to the map's first `keyframes` keyframes and `points` points, as they were taken up
  // before a run that changed nothing of them (Keyframe::frozen) added the rest: the others go,
  // with every observation in them.
  void KeepFirst(int keyframes, int points);

  // The map without its retired keyframes and the points they hosted: the others keep their order
  // and are numbered anew (ids, hosts, observations, hosted lists). Returns the new id of each old
  // keyframe (-1: retired).
  std::vector<int> DropRetired();

  Keyframe& keyframe(int id) { return *keyframes_[id]; }
  const Keyframe& keyframe(int id) const { return *keyframes_[id]; }
  Point& point(int id) { return points_[id]; }
  const Point& point(int id) const { return points_[id]; }
  int NumKeyframes() const { return static_cast<int>(keyframes_.size()); }
  int NumPoints() const { return static_cast<int>(points_.size()); }
  int NumLivePoints() const;

  // Memory: a keyframe keeps its pyramid only while it is used. LoadPyramids rebuilds the missing
  // pyramids of `ids` from their images and marks them used in the current epoch;
  // ReleaseUnusedPyramids ends an epoch (one mapped keyframe) and drops the pyramids not used in
  // the last `keep_epochs` epochs. Returns how many it rebuilt / dropped. A retired keyframe has
  // neither image nor pyramid and is never loaded.
  int LoadPyramids(const std::vector<int>& ids);
  int ReleaseUnusedPyramids(int keep_epochs);
  int NumLoadedPyramids() const;
  int NumPyramidsRebuilt() const { return pyramids_rebuilt_; }  // By LoadPyramids, in all.

  // How every residual of this map samples its images (photometric/residual.h); set before the
  // first point.
  Interpolation interpolation() const { return interpolation_; }
  void set_interpolation(Interpolation interpolation);

 private:
  int epoch_ = 0, pyramids_rebuilt_ = 0;
  Interpolation interpolation_ = Interpolation::kBilinear;
  std::vector<std::unique_ptr<Keyframe>> keyframes_;
  std::vector<Point> points_;
};

}  // namespace dsm
