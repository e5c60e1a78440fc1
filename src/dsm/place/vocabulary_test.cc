// SPDX-License-Identifier: MIT
#include "dsm/place/vocabulary.h"

#include <random>

#include <gtest/gtest.h>

#include "dsm/util/check.h"

namespace dsm {
namespace {

// Descriptors scattered around `centres` (each bit flipped with probability `flip`).
cv::Mat Around(const std::vector<BinaryDescriptor>& centres, int per_centre, double flip, std::mt19937& rng) {
  cv::Mat d(static_cast<int>(centres.size()) * per_centre, 32, CV_8U);
  std::bernoulli_distribution flipped(flip);
  for (size_t c = 0; c < centres.size(); ++c)
    for (int i = 0; i < per_centre; ++i) {
      BinaryDescriptor x = centres[c];
      for (int b = 0; b < 256; ++b)
        if (flipped(rng)) x[b / 64] ^= uint64_t{1} << (b % 64);
      std::memcpy(d.ptr<uint8_t>(static_cast<int>(c) * per_centre + i), x.data(), 32);
    }
  return d;
}

std::vector<BinaryDescriptor> RandomCentres(int n, std::mt19937& rng) {
  std::vector<BinaryDescriptor> c(n);
  for (auto& d : c)
    for (auto& w : d) w = (uint64_t{rng()} << 32) | rng();
  return c;
}

TEST(Vocabulary, WordsSeparateClustersAndScoresRankTheSamePlaceFirst) {
  std::mt19937 rng(3);
  const std::vector<BinaryDescriptor> centres = RandomCentres(64, rng);
  // Eight "places", each made of its own eight clusters.
  std::vector<cv::Mat> images;
  for (int place = 0; place < 8; ++place)
    images.push_back(Around({centres.begin() + 8 * place, centres.begin() + 8 * place + 8}, 20, 0.05, rng));
  const Vocabulary v = Vocabulary::Train(images, {4, 3, 8, 1});
  EXPECT_EQ(v.branching(), 4);
  EXPECT_EQ(v.levels(), 3);
  EXPECT_GE(v.NumWords(), 40);
  EXPECT_LE(v.NumWords(), 64);
  // Descriptors near one centre share their word.
  for (int c = 0; c < 64; c += 7) {
    const cv::Mat near = Around({centres[c]}, 6, 0.03, rng);
    const int word = v.Word(DescriptorRow(near, 0));
    for (int r = 1; r < near.rows; ++r) EXPECT_EQ(v.Word(DescriptorRow(near, r)), word) << "centre " << c;
  }
  // A new view of place 2 scores highest against place 2, and 1 against itself.
  const BowVector view = v.Transform(Around({centres.begin() + 16, centres.begin() + 24}, 10, 0.05, rng));
  int best = -1;
  double best_score = -1.0;
  for (int place = 0; place < 8; ++place) {
    const double s = Vocabulary::Score(view, v.Transform(images[place]));
    if (s > best_score) best_score = s, best = place;
  }
  EXPECT_EQ(best, 2);
  EXPECT_GT(best_score, 0.5);
  EXPECT_NEAR(Vocabulary::Score(view, view), 1.0, 1e-6);
  double sum = 0.0;
  for (const auto& [word, weight] : view) sum += weight;
  EXPECT_NEAR(sum, 1.0, 1e-5);
}

TEST(Vocabulary, RoundTripsThroughItsBytesAndRejectsDamagedOnes) {
  std::mt19937 rng(5);
  const std::vector<cv::Mat> images = {Around(RandomCentres(30, rng), 10, 0.05, rng),
                                       Around(RandomCentres(30, rng), 10, 0.05, rng)};
  const Vocabulary v = Vocabulary::Train(images, {5, 2, 8, 2});
  const std::string bytes = v.ToBytes();
  const Vocabulary w = Vocabulary::FromBytes(bytes, "copy");
  EXPECT_EQ(w.ToBytes(), bytes);
  EXPECT_EQ(w.Transform(images[0]), v.Transform(images[0]));
  // Training is deterministic.
  EXPECT_EQ(Vocabulary::Train(images, {5, 2, 8, 2}).ToBytes(), bytes);
  const auto rejected = [](const std::string& b) {
    try {
      Vocabulary::FromBytes(b, "voc.bin");
    } catch (const InputError& e) {
      return std::string(e.what()).find("voc.bin") != std::string::npos;
    }
    return false;
  };
  EXPECT_TRUE(rejected(bytes.substr(0, bytes.size() - 1)));
  EXPECT_TRUE(rejected(""));
  std::string header = bytes;
  header[0] = 'X';
  EXPECT_TRUE(rejected(header));
  std::string levels = bytes;
  levels[12] = 9;
  EXPECT_TRUE(rejected(levels));
  std::string weight = bytes;
  std::memset(&weight[weight.size() - 4], 0xff, 4);  // NaN.
  EXPECT_TRUE(rejected(weight));
  EXPECT_THROW(Vocabulary::Read("/nonexistent/voc.bin"), InputError);
}

TEST(Vocabulary, TheBuiltInOneHasItsWords) {
  const Vocabulary& v = Vocabulary::BuiltIn();
  EXPECT_EQ(v.branching(), 10);
  EXPECT_EQ(v.levels(), 4);
  EXPECT_GT(v.NumWords(), 5000);
}

}  // namespace
}  // namespace dsm
