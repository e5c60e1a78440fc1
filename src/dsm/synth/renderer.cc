// SPDX-License-Identifier: MIT
#include "dsm/synth/renderer.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <tbb/parallel_for.h>

namespace dsm::synth {

namespace {

constexpr int kTile = 16;

// Renders the pixels of rows v0 .. v1 - 1 seen from one pose, tile by tile; each tile tests only
// the primitives inside the cone of its corner rays.
void RenderRows(const Scene& scene, const PinholeCamera& cam, const SE3d& world_from_cam, int v0, int v1,
                Image<float>* albedo, Image<float>* depth) {
  const Eigen::Matrix3f R = world_from_cam.Rotation().cast<float>();
  const Eigen::Vector3f o = world_from_cam.Translation().cast<float>();
  const float inv_f = static_cast<float>(2.0 / (cam.fx + cam.fy));
  const float inv_fx = static_cast<float>(1.0 / cam.fx), inv_fy = static_cast<float>(1.0 / cam.fy);
  const float cx = static_cast<float>(cam.cx), cy = static_cast<float>(cam.cy);
  const auto corner_ray = [&](double u, double v) {
    return Eigen::Vector3f(R * Eigen::Vector3f(static_cast<float>((u - cam.cx) / cam.fx),
                                               static_cast<float>((v - cam.cy) / cam.fy), 1.f));
  };
  for (int u0 = 0; u0 < cam.width; u0 += kTile) {
    const int u1 = std::min(cam.width, u0 + kTile);
    // Half a pixel of margin around the tile's pixel centres.
    const Scene::Subset subset = scene.InCone(
        o, {corner_ray(u0 - 0.5, v0 - 0.5), corner_ray(u1 - 0.5, v0 - 0.5), corner_ray(u1 - 0.5, v1 - 0.5),
            corner_ray(u0 - 0.5, v1 - 0.5)});
    for (int v = v0; v < v1; ++v) {
      float* a_row = albedo->Row(v);
      float* d_row = depth ? depth->Row(v) : nullptr;
      for (int u = u0; u < u1; ++u) {
        const Eigen::Vector3f ray_cam((u - cx) * inv_fx, (v - cy) * inv_fy, 1.f);
        const float inv_norm = 1.f / ray_cam.norm();
        const Eigen::Vector3f dir = R * (ray_cam * inv_norm);
        Hit hit;
        if (!scene.Intersect(o, dir, subset, &hit)) {
          a_row[u] = 0.f;
          if (d_row) d_row[u] = 0.f;
          continue;
        }
        // Footprint of one pixel on the surface: distance * (pixel angle, ~cos(theta) / f
        // off-axis) stretched by 1 / cos(incidence) on oblique surfaces.
        const float footprint = hit.distance * inv_f * inv_norm / std::max(hit.cos_incidence, 0.2f);
        a_row[u] = EvaluateTexture(*hit.texture, hit.u, hit.v, footprint);
        if (d_row) d_row[u] = hit.distance * inv_norm;  // z = distance * cos(angle to the axis)
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
template <typename PoseOf>
void RenderInBands(const Scene& scene, const PinholeCamera& camera, int band_rows, const PoseOf& pose_of,
                   Image<float>* albedo, Image<float>* depth, bool parallel) {
  *albedo = Image<float>(camera.width, camera.height);
  if (depth) *depth = Image<float>(camera.width, camera.height);
  const int bands = (camera.height + band_rows - 1) / band_rows;
  const auto band = [&](int b) {
    const int v0 = b * band_rows;
    RenderRows(scene, camera, pose_of(v0), v0, std::min(camera.height, v0 + band_rows), albedo, depth);
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
  RenderInBands(scene, camera, kTile, [&](int) -> const SE3d& { return world_from_cam; }, albedo, depth, parallel);
}

void RenderRollingShutterFrame(const Scene& scene, const PinholeCamera& camera,
                               const std::vector<SE3d>& row_world_from_cam, Image<float>* albedo, Image<float>* depth,
                               bool parallel) {
  RenderInBands(scene, camera, 1, [&](int v) -> const SE3d& { return row_world_from_cam[v]; }, albedo, depth,
                parallel);
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

RenderedFrame RenderSequenceFrame(const SynthSequence& sequence, size_t i, const FormationOptions& formation) {
  RenderedFrame out;
  Image<float> albedo;
  if (sequence.line_delay_frames > 0.0) {
    RenderRollingShutterFrame(sequence.scene, sequence.camera, sequence.RowPoses(i), &albedo, &out.depth);
  } else {
    RenderFrame(sequence.scene, sequence.camera, sequence.world_from_cam[i], &albedo, &out.depth);
  }
  out.image = ToFloat(FormImage(albedo, sequence.photometry[i], formation));
  return out;
}

}  // namespace dsm::synth
