// SPDX-License-Identifier: MIT
#include "dsm/optimization/pba_world.h"

#include <random>

#include "dsm/synth/renderer.h"

namespace dsm::testing {

void BuildWorld(const std::vector<int>& frames, World* w, int stride, double blur_px, int width, int height) {
  synth::SynthOptions options;
  options.scene = "shake";
  options.width = width;
  options.height = height;
  w->seq = synth::MakeSequence(options);
  std::vector<Image<float>> depths;
  for (int f : frames) {
    synth::FormationOptions formation;
    formation.blur_sigma = blur_px;
    synth::RenderedFrame r = synth::RenderSequenceFrame(w->seq, f, formation);
    auto kf = std::make_unique<Keyframe>();
    kf->frame_index = f;
    kf->cam_from_world = w->seq.world_from_cam[f].Inverse();
    kf->pyramid = std::make_shared<const ImagePyramid>(r.image, 4);
    kf->error_model = DefaultErrorModel(RobustOptions{});
    w->true_cam_from_world.push_back(kf->cam_from_world);
    w->map.AddKeyframe(std::move(kf));
    depths.push_back(std::move(r.depth));
  }
  for (int host = 0; host < 2; ++host) {
    const Keyframe& kf = w->map.keyframe(host);
    for (int y = 8; y < height - 8; y += stride) {
      for (int x = 8; x < width - 8; x += stride) {
        const PixelGrad g = kf.Pyramid().At(0, x, y);
        if (g[1] * g[1] + g[2] * g[2] < 100.f || !(depths[host](x, y) > 0.f)) continue;
        Point p;
        p.host = host;
        p.pixel = Eigen::Vector2f(x, y);
        p.idepth = 1.f / depths[host](x, y);
        for (int t = 0; t < w->map.NumKeyframes(); ++t)
          if (t != host) p.observations.push_back({t, false});
        w->map.AddPoint(p);
      }
    }
  }
}

void Perturb(World* w, double scale) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int k = 1; k < w->map.NumKeyframes(); ++k) {
    Eigen::Matrix<double, 6, 1> xi;
    xi << 0.01 * n(rng), 0.01 * n(rng), 0.01 * n(rng), 0.006 * n(rng), 0.006 * n(rng), 0.006 * n(rng);
    w->map.keyframe(k).cam_from_world = SE3d::Exp(scale * xi) * w->map.keyframe(k).cam_from_world;
    w->map.keyframe(k).affine = {scale * 0.05 * n(rng), scale * 2.0 * n(rng)};
  }
  for (int i = 0; i < w->map.NumPoints(); ++i) w->map.point(i).idepth *= static_cast<float>(1.0 + scale * 0.05 * n(rng));
}

}  // namespace dsm::testing
