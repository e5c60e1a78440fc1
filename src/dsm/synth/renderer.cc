// SPDX-License-Identifier: MIT
#include "dsm/synth/renderer.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <tbb/parallel_for.h>

namespace dsm::synth {

namespace {

constexpr int kTile = 16;

// A pixel's ray: `unit` in the camera frame (zero: it sees nothing), z its component along the
// optical axis, and the angle the pixel spans over z.
struct PixelRay {
  Eigen::Vector3f unit;
  float z;
  float angle_over_z;
};

// The rays of a pinhole camera, computed as needed.
class PinholeRays {
 public:
  explicit PinholeRays(const PinholeCamera& cam)
      : cam_(cam),
        inv_f_(static_cast<float>(2.0 / (cam.fx + cam.fy))),
        inv_fx_(static_cast<float>(1.0 / cam.fx)),
        inv_fy_(static_cast<float>(1.0 / cam.fy)),
        cx_(static_cast<float>(cam.cx)),
        cy_(static_cast<float>(cam.cy)) {}
  int width() const { return cam_.width; }
  int height() const { return cam_.height; }
  bool Cone(int u0, int v0, int u1, int v1, std::array<Eigen::Vector3f, 4>* corners) const {
    const auto ray = [&](double u, double v) {
      return Eigen::Vector3f(static_cast<float>((u - cam_.cx) / cam_.fx), static_cast<float>((v - cam_.cy) / cam_.fy),
                             1.f);
    };
    *corners = {ray(u0 - 0.5, v0 - 0.5), ray(u1 - 0.5, v0 - 0.5), ray(u1 - 0.5, v1 - 0.5), ray(u0 - 0.5, v1 - 0.5)};
    return true;
  }
  // A pixel of a pinhole spans about cos(angle to the axis) / f = z / f.
  PixelRay At(int u, int v) const {
    const Eigen::Vector3f ray_cam((u - cx_) * inv_fx_, (v - cy_) * inv_fy_, 1.f);
    const float inv_norm = 1.f / ray_cam.norm();
    return {ray_cam * inv_norm, inv_norm, inv_f_};
  }

 private:
  const PinholeCamera& cam_;
  float inv_f_, inv_fx_, inv_fy_, cx_, cy_;
};

// The rays of a lens, from its table.
class TableRays {
 public:
  explicit TableRays(const LensRays& lens) : lens_(lens) {}
  int width() const { return lens_.width(); }
  int height() const { return lens_.height(); }
  bool Cone(int u0, int v0, int u1, int v1, std::array<Eigen::Vector3f, 4>* corners) const {
    return lens_.Cone(u0, v0, u1, v1, corners);
  }
  PixelRay At(int u, int v) const {
    const LensRays::Pixel& p = lens_.At(u, v);
    return {p.unit, p.unit.z(), p.unit.z() > 0.f ? p.angle / p.unit.z() : 0.f};
  }

 private:
  const LensRays& lens_;
};

// Renders the pixels of rows v0 .. v1 - 1 seen from one pose, tile by tile; each tile tests only
// the primitives inside the cone of its rays.
template <typename Rays>
void RenderRows(const Scene& scene, const Rays& rays, const SE3d& world_from_cam, int v0, int v1, Image<float>* albedo,
                Image<float>* depth) {
  const Eigen::Matrix3f R = world_from_cam.Rotation().cast<float>();
  const Eigen::Vector3f o = world_from_cam.Translation().cast<float>();
  for (int u0 = 0; u0 < rays.width(); u0 += kTile) {
    const int u1 = std::min(rays.width(), u0 + kTile);
    std::array<Eigen::Vector3f, 4> cone;
    Scene::Subset subset;
    if (rays.Cone(u0, v0, u1, v1, &cone)) {
      for (Eigen::Vector3f& c : cone) c = R * c;
      subset = scene.InCone(o, cone);
    } else {
      subset = scene.All();
    }
    for (int v = v0; v < v1; ++v) {
      float* a_row = albedo->Row(v);
      float* d_row = depth ? depth->Row(v) : nullptr;
      for (int u = u0; u < u1; ++u) {
        const PixelRay ray = rays.At(u, v);
        const Eigen::Vector3f dir = R * ray.unit;
        Hit hit;
        if (ray.z <= 0.f || !scene.Intersect(o, dir, subset, &hit)) {
          a_row[u] = 0.f;
          if (d_row) d_row[u] = 0.f;
          continue;
        }
        // Footprint of one pixel on the surface: distance * (the pixel's angle) stretched by
        // 1 / cos(incidence) on oblique surfaces.
        const float footprint = hit.distance * ray.angle_over_z * ray.z / std::max(hit.cos_incidence, 0.2f);
        a_row[u] = EvaluateTexture(*hit.texture, hit.u, hit.v, footprint);
        if (d_row) d_row[u] = hit.distance * ray.z;  // z = distance * cos(angle to the axis)
      }
    }
  }
}

// Separable Gaussian blur with clamped borders.
Image<float> GaussianBlur(const Image<float>& in, double sigma) {
  const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
  std::vector<float> kernel(2 * radius + 1);
  float sum = 0.f;
  for (int k = -radius; k <= radius; ++k) sum += kernel[k + radius] = static_cast<float>(std::exp(-0.5 * k * k / (sigma * sigma)));
  for (float& k : kernel) k /= sum;
  const int w = in.width(), h = in.height();
  Image<float> tmp(w, h), out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float acc = 0.f;
      for (int k = -radius; k <= radius; ++k) acc += kernel[k + radius] * in(std::clamp(x + k, 0, w - 1), y);
      tmp(x, y) = acc;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float acc = 0.f;
      for (int k = -radius; k <= radius; ++k) acc += kernel[k + radius] * tmp(x, std::clamp(y + k, 0, h - 1));
      out(x, y) = acc;
    }
  return out;
}

}  // namespace

namespace {

// The frame in bands of `band_rows` rows, band b (rows from v0 = b * band_rows) seen from
// pose_of(v0).
template <typename Rays, typename PoseOf>
void RenderInBands(const Scene& scene, const Rays& rays, int band_rows, const PoseOf& pose_of, Image<float>* albedo,
                   Image<float>* depth, bool parallel) {
  const int width = rays.width(), height = rays.height();
  *albedo = Image<float>(width, height);
  if (depth) *depth = Image<float>(width, height);
  const int bands = (height + band_rows - 1) / band_rows;
  const auto band = [&](int b) {
    const int v0 = b * band_rows;
    RenderRows(scene, rays, pose_of(v0), v0, std::min(height, v0 + band_rows), albedo, depth);
  };
  if (parallel) {
    tbb::parallel_for(0, bands, band);
  } else {
    for (int b = 0; b < bands; ++b) band(b);
  }
}

}  // namespace

void RenderFrame(const Scene& scene, const PinholeCamera& camera, const SE3d& world_from_cam, Image<float>* albedo,
                 Image<float>* depth, bool parallel) {
  RenderInBands(scene, PinholeRays(camera), kTile,
                [&](int) -> const SE3d& { return world_from_cam; }, albedo, depth, parallel);
}

void RenderRollingShutterFrame(const Scene& scene, const PinholeCamera& camera,
                               const std::vector<SE3d>& row_world_from_cam, Image<float>* albedo, Image<float>* depth,
                               bool parallel) {
  RenderInBands(scene, PinholeRays(camera), 1,
                [&](int v) -> const SE3d& { return row_world_from_cam[v]; }, albedo, depth, parallel);
}

void RenderFrame(const Scene& scene, const LensRays& lens, const SE3d& world_from_cam, Image<float>* albedo,
                 Image<float>* depth, bool parallel) {
  RenderInBands(scene, TableRays(lens), kTile,
                [&](int) -> const SE3d& { return world_from_cam; }, albedo, depth, parallel);
}

void RenderRollingShutterFrame(const Scene& scene, const LensRays& lens, const std::vector<SE3d>& row_world_from_cam,
                               Image<float>* albedo, Image<float>* depth, bool parallel) {
  RenderInBands(scene, TableRays(lens), 1,
                [&](int v) -> const SE3d& { return row_world_from_cam[v]; }, albedo, depth, parallel);
}

Image<float> MakeVignette(int width, int height, double strength) {
  Image<float> v(width, height);
  const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
  const double r2_corner = cx * cx + cy * cy;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      v(x, y) = static_cast<float>(1.0 - strength * ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / r2_corner);
  return v;
}

Image<uint8_t> FormImage(const Image<float>& albedo, const Photometry& p, const FormationOptions& options) {
  Image<float> irradiance(albedo.width(), albedo.height());
  const float scale = static_cast<float>(p.gain * (p.exposure_ms / 10.0) * 255.0);
  for (int y = 0; y < albedo.height(); ++y)
    for (int x = 0; x < albedo.width(); ++x) {
      float v = scale * albedo(x, y);
      if (options.vignette) v *= (*options.vignette)(x, y);
      irradiance(x, y) = v;
    }
  if (options.blur_sigma > 0.0) irradiance = GaussianBlur(irradiance, options.blur_sigma);
  std::mt19937 rng(options.noise_seed);
  std::normal_distribution<float> noise(0.f, static_cast<float>(options.noise_sigma));
  Image<uint8_t> out(albedo.width(), albedo.height());
  for (size_t i = 0; i < out.size(); ++i) {
    float v = irradiance.data()[i] + p.offset;
    if (options.noise_sigma > 0.0) v += noise(rng);
    out.data()[i] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  return out;
}

void RenderSequenceAlbedo(const SynthSequence& sequence, size_t i, Image<float>* albedo, Image<float>* depth,
                          bool parallel) {
  const bool rolling = sequence.line_delay_frames > 0.0;
  if (sequence.lens && rolling) {
    RenderRollingShutterFrame(sequence.scene, *sequence.lens, sequence.RowPoses(i), albedo, depth, parallel);
  } else if (sequence.lens) {
    RenderFrame(sequence.scene, *sequence.lens, sequence.world_from_cam[i], albedo, depth, parallel);
  } else if (rolling) {
    RenderRollingShutterFrame(sequence.scene, sequence.camera, sequence.RowPoses(i), albedo, depth, parallel);
  } else {
    RenderFrame(sequence.scene, sequence.camera, sequence.world_from_cam[i], albedo, depth, parallel);
  }
}

RenderedFrame RenderSequenceFrame(const SynthSequence& sequence, size_t i, const FormationOptions& formation) {
  RenderedFrame out;
  Image<float> albedo;
  RenderSequenceAlbedo(sequence, i, &albedo, &out.depth);
  out.image = ToFloat(FormImage(albedo, sequence.photometry[i], formation));
  return out;
}

}  // namespace dsm::synth
