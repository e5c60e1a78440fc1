// SPDX-License-Identifier: MIT
#include "dsm/place/vocabulary.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <set>

#include <tbb/task_group.h>

#include "dsm/util/check.h"

// The built-in vocabulary's bytes (vocabulary_data.S).
extern "C" const char dsm_vocabulary_begin[];
extern "C" const char dsm_vocabulary_end[];

namespace dsm {

namespace {

constexpr char kMagic[8] = {'D', 'S', 'M', 'V', 'O', 'C', '0', '1'};

int NumNodes(int branching, int levels) {  // Without the root.
  int n = 0, width = 1;
  for (int l = 0; l < levels; ++l) n += width *= branching;
  return n;
}

// k-majority clustering of `members` (indices into `all`) into at most `k` centres; returns each
// member's cluster in `assignment` and whether each centre received members.
std::vector<BinaryDescriptor> Cluster(const std::vector<BinaryDescriptor>& all, const std::vector<int>& members, int k,
                                      int iterations, uint32_t seed, std::vector<int>* assignment) {
  const int n = static_cast<int>(members.size());
  std::vector<BinaryDescriptor> centres;
  assignment->assign(n, 0);
  if (n <= k) {
    for (int i = 0; i < n; ++i) centres.push_back(all[members[i]]), (*assignment)[i] = i;
    return centres;
  }
  // k-means++ seeding: each next centre drawn with probability proportional to the squared
  // distance to the nearest centre so far.
  std::mt19937 rng(seed);
  centres.push_back(all[members[std::uniform_int_distribution<int>(0, n - 1)(rng)]]);
  std::vector<double> nearest(n, std::numeric_limits<double>::max());
  while (static_cast<int>(centres.size()) < k) {
    double total = 0.0;
    for (int i = 0; i < n; ++i) {
      const double d = HammingDistance(all[members[i]], centres.back());
      nearest[i] = std::min(nearest[i], d * d);
      total += nearest[i];
    }
    if (total <= 0.0) break;  // Every member equals a centre.
    double pick = std::uniform_real_distribution<double>(0.0, total)(rng);
    int chosen = n - 1;
    for (int i = 0; i < n; ++i)
      if ((pick -= nearest[i]) <= 0.0) {
        chosen = i;
        break;
      }
    centres.push_back(all[members[chosen]]);
  }
  const int c = static_cast<int>(centres.size());
  std::vector<std::array<int, 256>> ones(c);
  std::vector<int> counts(c);
  for (int it = 0; it < iterations; ++it) {
    bool changed = it == 0;
    for (int i = 0; i < n; ++i) {
      int best = 0, best_d = std::numeric_limits<int>::max();
      for (int j = 0; j < c; ++j) {
        const int d = HammingDistance(all[members[i]], centres[j]);
        if (d < best_d) best_d = d, best = j;
      }
      if ((*assignment)[i] != best) changed = true;
      (*assignment)[i] = best;
    }
    if (!changed) break;
    for (auto& o : ones) o.fill(0);
    std::fill(counts.begin(), counts.end(), 0);
    for (int i = 0; i < n; ++i) {
      const BinaryDescriptor& d = all[members[i]];
      auto& o = ones[(*assignment)[i]];
      ++counts[(*assignment)[i]];
      for (int w = 0; w < 4; ++w)
        for (uint64_t bits = d[w]; bits != 0; bits &= bits - 1) ++o[64 * w + std::countr_zero(bits)];
    }
    for (int j = 0; j < c; ++j) {
      if (counts[j] == 0) continue;  // Keeps its centre.
      BinaryDescriptor centre{};
      for (int b = 0; b < 256; ++b)
        if (2 * ones[j][b] > counts[j]) centre[b / 64] |= uint64_t{1} << (b % 64);
      centres[j] = centre;
    }
  }
  return centres;
}

template <typename T>
void Append(std::string* out, const T& value) {
  out->append(reinterpret_cast<const char*>(&value), sizeof(T));
}

}  // namespace

BinaryDescriptor DescriptorRow(const cv::Mat& descriptors, int row) {
  DSM_CHECK(descriptors.type() == CV_8U && descriptors.cols == 32, "ORB descriptors are rows of 32 bytes");
  BinaryDescriptor d;
  std::memcpy(d.data(), descriptors.ptr<uint8_t>(row), 32);
  return d;
}

int HammingDistance(const BinaryDescriptor& a, const BinaryDescriptor& b) {
  return std::popcount(a[0] ^ b[0]) + std::popcount(a[1] ^ b[1]) + std::popcount(a[2] ^ b[2]) +
         std::popcount(a[3] ^ b[3]);
}

Vocabulary Vocabulary::Train(const std::vector<cv::Mat>& images, const VocabularyOptions& options) {
  if (options.branching < 2 || options.branching > 32 || options.levels < 1 || options.levels > 6 ||
      NumNodes(options.branching, options.levels) > 20000000)
    throw InputError("vocabulary: branching must be within 2..32 and levels within 1..6 (at most 2e7 nodes)");
  std::vector<BinaryDescriptor> all;
  std::vector<int> image_of;
  for (size_t i = 0; i < images.size(); ++i)
    for (int r = 0; r < images[i].rows; ++r) all.push_back(DescriptorRow(images[i], r)), image_of.push_back(i);
  if (all.empty()) throw InputError("vocabulary: no descriptors to train on");
  Vocabulary v;
  v.branching_ = options.branching;
  v.levels_ = options.levels;
  const int k = options.branching;
  v.nodes_.assign(NumNodes(k, options.levels), BinaryDescriptor{});
  v.used_.assign(v.nodes_.size(), 0);
  std::vector<int> leaf_of(all.size(), 0);  // Node index.
  // Each node's members are split among its children; the subtrees are independent (their own
  // seeds), so they run as parallel tasks with the same result as in order.
  tbb::task_group tasks;
  std::function<void(int, int, std::vector<int>)> split = [&](int node, int level, std::vector<int> members) {
    if (level == options.levels) {
      for (int m : members) leaf_of[m] = node;
      return;
    }
    std::vector<int> assignment;
    const std::vector<BinaryDescriptor> centres =
        Cluster(all, members, k, options.iterations, options.seed * 7919u + static_cast<uint32_t>(node), &assignment);
    std::vector<std::vector<int>> children(centres.size());
    for (size_t i = 0; i < members.size(); ++i) children[assignment[i]].push_back(members[i]);
    for (size_t j = 0; j < centres.size(); ++j) {
      if (children[j].empty()) continue;
      const int child = node * k + 1 + static_cast<int>(j);
      v.nodes_[child - 1] = centres[j];
      v.used_[child - 1] = 1;
      auto m = std::make_shared<std::vector<int>>(std::move(children[j]));
      tasks.run([&split, child, level, m] { split(child, level + 1, std::move(*m)); });
    }
  };
  std::vector<int> everything(all.size());
  for (size_t i = 0; i < all.size(); ++i) everything[i] = static_cast<int>(i);
  split(0, 0, std::move(everything));
  tasks.wait();
  // idf_w = log(N / N_w) over the training images.
  const int first_leaf = v.FirstLeaf();
  v.idf_.assign(v.nodes_.size() + 1 - first_leaf, 0.f);
  std::vector<int> images_with(v.idf_.size(), 0);
  std::set<std::pair<int, int>> seen;  // (image, leaf)
  for (size_t i = 0; i < all.size(); ++i)
    if (seen.emplace(image_of[i], leaf_of[i] - first_leaf).second) ++images_with[leaf_of[i] - first_leaf];
  for (size_t w = 0; w < v.idf_.size(); ++w)
    if (images_with[w] > 0) v.idf_[w] = static_cast<float>(std::log(static_cast<double>(images.size()) / images_with[w]));
  return v;
}

int Vocabulary::FirstLeaf() const { return 1 + NumNodes(branching_, levels_ - 1); }

int Vocabulary::NumWords() const {
  const int first = FirstLeaf();
  int n = 0;
  for (size_t i = first - 1; i < used_.size(); ++i) n += used_[i];
  return n;
}

int Vocabulary::Word(const BinaryDescriptor& d) const {
  int node = 0;
  for (int level = 0; level < levels_; ++level) {
    int best = -1, best_d = std::numeric_limits<int>::max();
    for (int j = 1; j <= branching_; ++j) {
      const int child = node * branching_ + j;
      if (!used_[child - 1]) continue;
      const int dist = HammingDistance(d, nodes_[child - 1]);
      if (dist < best_d) best_d = dist, best = child;
    }
    if (best < 0) break;  // Not reached by a trained vocabulary: every used node has a used child.
    node = best;
  }
  return node - FirstLeaf();
}

BowVector Vocabulary::Transform(const cv::Mat& descriptors, std::vector<int>* words) const {
  DSM_CHECK(!empty(), "an empty vocabulary has no words");
  if (words) words->assign(descriptors.rows, -1);
  std::vector<int> all(descriptors.rows);
  for (int r = 0; r < descriptors.rows; ++r) {
    all[r] = Word(DescriptorRow(descriptors, r));
    if (words) (*words)[r] = all[r];
  }
  std::sort(all.begin(), all.end());
  BowVector bow;
  double total = 0.0;
  for (size_t i = 0; i < all.size();) {
    size_t j = i;
    while (j < all.size() && all[j] == all[i]) ++j;
    const float weight = static_cast<float>(j - i) * idf_[all[i]];
    if (weight > 0.f) bow.emplace_back(all[i], weight), total += weight;
    i = j;
  }
  for (auto& [word, weight] : bow) weight = static_cast<float>(weight / total);
  return bow;
}

double Vocabulary::Score(const BowVector& a, const BowVector& b) {
  // 1 - 0.5 |a - b|_1 = 0.5 * sum over common words of (a_w + b_w - |a_w - b_w|) for L1-unit vectors.
  double sum = 0.0;
  auto i = a.begin(), j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (i->first < j->first) {
      ++i;
    } else if (j->first < i->first) {
      ++j;
    } else {
      sum += i->second + j->second - std::abs(i->second - j->second);
      ++i, ++j;
    }
  }
  return 0.5 * sum;
}

std::string Vocabulary::ToBytes() const {
  // Magic, branching and levels (int32), then per node but the root its used flag (1 byte) and
  // descriptor (32 bytes), then per leaf its idf (float32); little-endian.
  std::string out(kMagic, sizeof(kMagic));
  Append(&out, static_cast<int32_t>(branching_));
  Append(&out, static_cast<int32_t>(levels_));
  for (size_t i = 0; i < nodes_.size(); ++i) {
    Append(&out, used_[i]);
    Append(&out, nodes_[i]);
  }
  for (float idf : idf_) Append(&out, idf);
  return out;
}

Vocabulary Vocabulary::FromBytes(const std::string& bytes, const std::string& name) {
  const auto bad = [&](const std::string& why) { return InputError(name + ": not a dsm vocabulary file (" + why + ")"); };
  size_t at = 0;
  const auto take = [&](void* to, size_t n) {
    if (bytes.size() - at < n) throw bad("truncated");
    std::memcpy(to, bytes.data() + at, n);
    at += n;
  };
  char magic[sizeof(kMagic)];
  take(magic, sizeof(magic));
  if (std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) throw bad("wrong header");
  int32_t branching, levels;
  take(&branching, 4), take(&levels, 4);
  if (branching < 2 || branching > 32 || levels < 1 || levels > 6 || NumNodes(branching, levels) > 20000000)
    throw bad("branching " + std::to_string(branching) + ", levels " + std::to_string(levels));
  Vocabulary v;
  v.branching_ = branching, v.levels_ = levels;
  const int nodes = NumNodes(branching, levels);
  if (bytes.size() != sizeof(kMagic) + 8 + static_cast<size_t>(nodes) * 33 + 4 * static_cast<size_t>(nodes + 1 - v.FirstLeaf()))
    throw bad("size " + std::to_string(bytes.size()) + " bytes does not match its tree");
  v.nodes_.resize(nodes);
  v.used_.resize(nodes);
  for (int i = 0; i < nodes; ++i) {
    take(&v.used_[i], 1);
    take(v.nodes_[i].data(), 32);
    if (v.used_[i] > 1) throw bad("node flag");
  }
  v.idf_.resize(nodes + 1 - v.FirstLeaf());
  take(v.idf_.data(), 4 * v.idf_.size());
  for (float idf : v.idf_)
    if (!(idf >= 0.f && idf < 1e3f)) throw bad("word weight");
  // Every used inner node must lead to a used leaf.
  for (int node = 1; node < v.FirstLeaf(); ++node) {
    if (!v.used_[node - 1]) continue;
    bool any = false;
    for (int j = 1; j <= branching; ++j) any |= v.used_[node * branching + j - 1] != 0;
    if (!any) throw bad("a node without words");
  }
  return v;
}

Vocabulary Vocabulary::Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the vocabulary file");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return FromBytes(bytes, path);
}

void Vocabulary::Write(const std::string& path) const {
  std::ofstream out(path, std::ios::binary);
  const std::string bytes = ToBytes();
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw InputError(path + ": cannot write the vocabulary file");
}

const Vocabulary& Vocabulary::BuiltIn() {
  static const Vocabulary v = [] {
    const std::string bytes(dsm_vocabulary_begin, dsm_vocabulary_end);
    if (bytes.empty()) throw InputError("dsm was built without a vocabulary (data/orb_vocabulary.bin is empty)");
    return FromBytes(bytes, "the built-in vocabulary");
  }();
  return v;
}

}  // namespace dsm
