// SPDX-License-Identifier: MIT
#include "dsm/mapping/candidate.h"

#include <random>

#include <gtest/gtest.h>

#include "dsm/mapping/candidate_selector.h"
#include "dsm/photometric/residual.h"
#include "dsm/synth/renderer.h"

namespace dsm {
namespace {

struct Frame {
  ImagePyramid pyramid;
  Image<float> depth;
};

Frame Render(const synth::SynthSequence& seq, int i) {
  synth::FormationOptions formation;
  formation.noise_sigma = 1.0;
  formation.noise_seed = i;
  synth::RenderedFrame r = synth::RenderSequenceFrame(seq, i, formation);
  return {ImagePyramid(r.image, 4), std::move(r.depth)};
}

synth::SynthSequence Sequence(const std::string& scene) {
  synth::SynthOptions options;
  options.scene = scene;
  options.width = 320;
  options.height = 240;
  return synth::MakeSequence(options);
}

TEST(CandidateSelector, HitsTheTargetCountWellSpread) {
  const auto seq = Sequence("loop");
  const Frame f = Render(seq, 20);
  CandidateSelectorOptions options;
  options.target_count = 600;
  const auto selected = SelectCandidates(f.pyramid, options);
  EXPECT_GT(selected.size(), 0.85 * 600);
  EXPECT_LT(selected.size(), 1.15 * 600);
  // Spread: every 80 x 80 region holds candidates.
  for (int by = 0; by < 3; ++by)
    for (int bx = 0; bx < 4; ++bx) {
      int n = 0;
      for (const auto& s : selected) n += int(s.pixel.x()) / 80 == bx && int(s.pixel.y()) / 80 == by;
      EXPECT_GT(n, 5) << bx << " " << by;
    }
}

// Left half: smooth shading (no depth information) under Gaussian noise of `sigma`; right half: a
// sharp texture (a 4-px checker whose squares vary in brightness) under the same noise.
Image<float> HalfFlatHalfTextured(float sigma, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.f, sigma);
  std::uniform_real_distribution<float> shade(40.f, 200.f);
  Image<float> image(320, 240);
  Image<float> squares(80, 60);
  for (size_t i = 0; i < squares.size(); ++i) squares.data()[i] = shade(rng);
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) {
      const float smooth = 100.f + 0.1f * x + 0.05f * y;
      image(x, y) = (x < 160 ? smooth : squares(x / 4, y / 4)) + noise(rng);
    }
  return image;
}

TEST(CandidateSelector, EstimatesTheNoiseOfFlatBlocks) {
  for (const float sigma : {1.f, 3.f, 6.f}) {
    const ImagePyramid pyramid(HalfFlatHalfTextured(sigma, 7), 4);
    const BlockThresholds t = ComputeBlockThresholds(pyramid, CandidateSelectorOptions{});
    // Block column 2 (x 64..95) and its neighbours lie in the flat half.
    for (int by = 1; by < t.noise_sigma.height() - 1; ++by) EXPECT_NEAR(t.noise_sigma(2, by), sigma, 0.12 * sigma) << by;
  }
}

TEST(CandidateSelector, KeepsOffNoiseOnFlatAreas) {
  const ImagePyramid pyramid(HalfFlatHalfTextured(6.f, 3), 4);
  CandidateSelectorOptions options;
  options.target_count = 600;
  const auto count_flat = [&](const CandidateSelectorOptions& o) {
    int flat = 0;
    for (const auto& s : SelectCandidates(pyramid, o)) flat += s.pixel.x() < 150;
    return flat;
  };
  // Without the noise floors, half the weak cells of the flat half take a noise pixel.
  CandidateSelectorOptions no_floor = options;
  no_floor.noise_factor = 0.f;
  no_floor.contrast_factor = 0.f;
  EXPECT_GT(count_flat(no_floor), 150);
  // With it, only the noise's own 4-sigma tail: P = exp(-8) of ~38 k pixels, ~13.
  EXPECT_LT(count_flat(options), 30);
  EXPECT_GT(SelectCandidates(pyramid, options).size(), 0.85 * 600);  // The textured half has them all.
}

TEST(CandidateSelector, PatternContrastIsTheStandardDeviationOfThePattern) {
  Image<float> image(9, 9);
  for (size_t i = 0; i < image.size(); ++i) image.data()[i] = 50.f;
  // Four of the eight pattern pixels at 60, four at 40: mean 50, standard deviation 10.
  for (int i = 0; i < kPatternSize; ++i) image(4 + kPattern[i][0], 4 + kPattern[i][1]) = i % 2 ? 60.f : 40.f;
  EXPECT_NEAR(PatternContrast(image, 4, 4), 10.f, 1e-5f);
  image(6, 6) = 1000.f;  // Not a pattern pixel of (4, 4).
  EXPECT_NEAR(PatternContrast(image, 4, 4), 10.f, 1e-5f);
}

// Left half: a checker of 4-px squares whose brightness varies by +-6 grey levels (standard
// deviation 3.5), under noise of `sigma` (4 below): with the noise's help some of its edges pass
// the gradient tests, but their patterns have hardly more contrast than the noise; right half: a
// sharp checker as in HalfFlatHalfTextured.
Image<float> HalfFaintHalfTextured(float sigma, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.f, sigma);
  std::uniform_real_distribution<float> faint(94.f, 106.f), shade(40.f, 200.f);
  Image<float> image(320, 240);
  Image<float> squares(80, 60);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 80; ++x) squares(x, y) = x < 40 ? faint(rng) : shade(rng);
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) image(x, y) = squares(x / 4, y / 4) + noise(rng);
  return image;
}

TEST(CandidateSelector, KeepsOffPatternsWithoutContrast) {
  const ImagePyramid pyramid(HalfFaintHalfTextured(4.f, 5), 4);
  CandidateSelectorOptions options;
  options.target_count = 600;
  CandidateSelectorOptions no_floor = options;
  no_floor.contrast_factor = 0.f;
  const auto with = SelectCandidates(pyramid, options), without = SelectCandidates(pyramid, no_floor);
  const auto split = [](const std::vector<SelectedPixel>& sel) {
    std::vector<Eigen::Vector2f> left, right;
    for (const auto& s : sel) (s.pixel.x() < 150 ? left : right).push_back(s.pixel);
    return std::make_pair(left, right);
  };
  const auto [with_left, with_right] = split(with);
  const auto [without_left, without_right] = split(without);
  EXPECT_GT(without_left.size(), 50u);  // The faint half's edges pass the gradient tests.
  EXPECT_LT(with_left.size(), 0.1 * without_left.size()) << with_left.size() << " of " << without_left.size();
  std::printf("faint half: %zu picks without the contrast floor, %zu with it\n", without_left.size(), with_left.size());
  // A dropped pick leaves its cell empty: the textured half keeps the same picks, not a denser grid.
  EXPECT_EQ(with_right, without_right);
}

TEST(Candidate, EpipolarSearchFindsTheTrueDepth) {
  const auto seq = Sequence("shake");
  const Frame host = Render(seq, 0), frame = Render(seq, 8);
  const SE3d frame_from_host = seq.world_from_cam[8].Inverse() * seq.world_from_cam[0];
  CandidateSelectorOptions options;
  options.target_count = 400;
  int good = 0, contained = 0, total = 0;
  for (const auto& s : SelectCandidates(host.pyramid, options)) {
    Candidate c;
    if (!MakeCandidate(host.pyramid, s.pixel, &c)) continue;
    const float true_idepth = 1.f / host.depth(int(s.pixel.x()), int(s.pixel.y()));
    ++total;
    if (TraceCandidate(&c, frame.pyramid, seq.camera, frame_from_host, {}, EpipolarOptions{}) != TraceStatus::kGood) continue;
    ++good;
    // The interval (widened by 10% for interpolation effects) holds the true inverse depth.
    const float margin = 0.1f * (c.idepth_max - c.idepth_min) + 0.01f * true_idepth;
    contained += true_idepth >= c.idepth_min - margin && true_idepth <= c.idepth_max + margin;
  }
  EXPECT_GT(good, 0.6 * total);
  EXPECT_GT(contained, 0.9 * good) << good << " good of " << total;
}

TEST(Candidate, SecondTraceNarrowsTheInterval) {
  const auto seq = Sequence("shake");
  const Frame host = Render(seq, 0), f1 = Render(seq, 4), f2 = Render(seq, 12);
  CandidateSelectorOptions options;
  options.target_count = 200;
  int narrowed = 0, good = 0;
  for (const auto& s : SelectCandidates(host.pyramid, options)) {
    Candidate c;
    if (!MakeCandidate(host.pyramid, s.pixel, &c)) continue;
    if (TraceCandidate(&c, f1.pyramid, seq.camera, seq.world_from_cam[4].Inverse() * seq.world_from_cam[0], {}, {}) !=
        TraceStatus::kGood)
      continue;
    const float first = c.idepth_max - c.idepth_min;
    if (TraceCandidate(&c, f2.pyramid, seq.camera, seq.world_from_cam[12].Inverse() * seq.world_from_cam[0], {}, {}) !=
        TraceStatus::kGood)
      continue;
    ++good;
    narrowed += (c.idepth_max - c.idepth_min) < first;
  }
  EXPECT_GT(good, 50);
  EXPECT_GT(narrowed, 0.7 * good);
}

}  // namespace
}  // namespace dsm
