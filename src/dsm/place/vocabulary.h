// SPDX-License-Identifier: MIT
// A vocabulary of binary visual words for place recognition (Galvez-Lopez and Tardos, "Bags of
// Binary Words", T-RO 2012): a tree of `branching`^`levels` leaves over 256-bit ORB descriptors,
// built by hierarchical k-majority clustering (k-means with the Hamming distance, each centre the
// bitwise majority of its members, seeded by k-means++).
//
// A descriptor's word is the leaf reached by descending to the nearest child at each level. An
// image is a bag of words weighted by TF-IDF: v_w = (n_w / n) * idf_w, idf_w = log(N / N_w) over
// the N training images of which N_w contain w, and the vector is L1-normalised. Two images score
//   s(v, u) = 1 - 0.5 * | v - u |_1  in [0, 1]  (1: the same bag).
//
// The tree is complete: node i's children are i * branching + 1 .. i * branching + branching (root
// 0), so the file holds the descriptors level by level and the leaves' weights; a child that
// received no training descriptors is marked empty and never descended to.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace dsm {

using BinaryDescriptor = std::array<uint64_t, 4>;  // 256 bits, as ORB's.

// (word, weight), by increasing word; weights sum to 1.
using BowVector = std::vector<std::pair<int, float>>;

struct VocabularyOptions {
  int branching = 10;
  int levels = 4;
  int iterations = 8;  // k-majority iterations per node.
  uint32_t seed = 1;
};

class Vocabulary {
 public:
  Vocabulary() = default;
  // One cv::Mat per training image: rows of 32-byte descriptors (CV_8U). Deterministic.
  static Vocabulary Train(const std::vector<cv::Mat>& images, const VocabularyOptions& options);
  // Throws InputError naming `path` when it is missing, damaged or not a vocabulary file.
  static Vocabulary Read(const std::string& path);
  static Vocabulary FromBytes(const std::string& bytes, const std::string& name);
  // The vocabulary built into dsm (data/orb_vocabulary.bin, trained by `dsm vocabulary`).
  static const Vocabulary& BuiltIn();
  void Write(const std::string& path) const;  // Throws InputError when it cannot be written.
  std::string ToBytes() const;

  bool empty() const { return levels_ == 0; }
  int branching() const { return branching_; }
  int levels() const { return levels_; }
  int NumWords() const;  // Leaves that received training descriptors.

  // The word of one descriptor (its leaf's index among the leaves).
  int Word(const BinaryDescriptor& d) const;
  // The bag of `descriptors` (rows of 32 bytes); `words`: each row's word, when given.
  BowVector Transform(const cv::Mat& descriptors, std::vector<int>* words = nullptr) const;
  static double Score(const BowVector& a, const BowVector& b);

 private:
  int FirstLeaf() const;  // Node index of leaf 0.
  int branching_ = 0, levels_ = 0;
  std::vector<BinaryDescriptor> nodes_;  // Every node but the root, by index - 1.
  std::vector<uint8_t> used_;            // Per node but the root: received training descriptors.
  std::vector<float> idf_;               // Per leaf.
};

BinaryDescriptor DescriptorRow(const cv::Mat& descriptors, int row);
int HammingDistance(const BinaryDescriptor& a, const BinaryDescriptor& b);

}  // namespace dsm
