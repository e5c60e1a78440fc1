// SPDX-License-Identifier: MIT
#include "dsm/synth/scenes.h"

#include <cmath>
#include <algorithm>
#include <random>

#include "dsm/image/defects.h"
#include "dsm/io/calibration_io.h"
#include "dsm/synth/smooth_step.h"
#include "dsm/util/check.h"

namespace dsm::synth {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;
constexpr int64_t kStartNs = 1600000000000000000LL;  // A realistic epoch, beyond 2^53 ns.

// Smooth pseudo-random jitter: a few sines with seeded phases, amplitude ~1.
struct Jitter {
  double phase[3][3];
  explicit Jitter(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, kTwoPi);
    for (auto& axis : phase)
      for (double& p : axis) p = u(rng);
  }
  Eigen::Vector3d At(double t_s) const {
    static constexpr double kFreq[3] = {0.31, 0.73, 1.37};  // Hz
    Eigen::Vector3d j = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) j[a] += std::sin(kTwoPi * kFreq[k] * t_s + phase[a][k]) / (k + 1.5);
    return j;
  }
};

Texture MakeTexture(std::mt19937& rng, float base, float contrast, float scale, float lines = 0.f, float weak = 0.f) {
  return Texture{static_cast<uint32_t>(rng()), base, contrast, scale, lines, weak};
}

// A room 8 x 6 x 3 m centred at the origin, with boxes and cylinders near the walls.
void FurnishedRoom(std::mt19937& rng, Scene* scene) {
  // Walls -x, +x, -y, +y, floor, ceiling.
  scene->AddRoom({-4, -3, 0}, {4, 3, 3},
                 {MakeTexture(rng, 0.55f, 0.35f, 1.2f), MakeTexture(rng, 0.45f, 0.35f, 0.9f, 1.0f),
                  MakeTexture(rng, 0.5f, 0.3f, 1.5f, 0.f, 0.35f), MakeTexture(rng, 0.6f, 0.3f, 1.1f),
                  MakeTexture(rng, 0.4f, 0.3f, 1.0f, 0.6f), MakeTexture(rng, 0.7f, 0.2f, 2.0f, 0.f, 0.5f)});
  scene->AddBox({2.9f, -1.9f, 0.f}, {3.6f, -0.9f, 0.9f}, MakeTexture(rng, 0.65f, 0.3f, 0.5f));
  scene->AddBox({-3.7f, 0.6f, 0.f}, {-3.0f, 1.8f, 1.4f}, MakeTexture(rng, 0.35f, 0.3f, 0.6f, 0.35f));
  scene->AddBox({-1.0f, 2.3f, 0.f}, {0.4f, 2.8f, 0.7f}, MakeTexture(rng, 0.55f, 0.35f, 0.4f));
  scene->AddBox({0.5f, -2.8f, 0.8f}, {1.7f, -2.5f, 1.6f}, MakeTexture(rng, 0.3f, 0.25f, 0.5f));
  scene->AddCylinder({{2.9f, 2.1f}, 0.35f, 0.f, 2.2f, MakeTexture(rng, 0.5f, 0.35f, 0.4f)});
  scene->AddCylinder({{-2.8f, -2.0f}, 0.25f, 0.f, 3.f, MakeTexture(rng, 0.6f, 0.3f, 0.3f)});
  scene->AddCylinder({{1.0f, 2.4f}, 0.2f, 0.f, 1.2f, MakeTexture(rng, 0.4f, 0.3f, 0.3f)});
}

// A corridor along +x: 24 m long, 2.4 m wide, 2.6 m high, with boxes along the walls.
void Corridor(std::mt19937& rng, Scene* scene) {
  scene->AddRoom({-2, -1.2f, 0}, {22, 1.2f, 2.6f},
                 {MakeTexture(rng, 0.45f, 0.3f, 0.8f), MakeTexture(rng, 0.6f, 0.3f, 0.8f),
                  MakeTexture(rng, 0.5f, 0.35f, 1.3f, 0.f, 0.3f), MakeTexture(rng, 0.55f, 0.35f, 1.0f, 1.2f),
                  MakeTexture(rng, 0.35f, 0.3f, 1.0f, 0.5f), MakeTexture(rng, 0.7f, 0.25f, 1.5f, 0.f, 0.4f)});
  for (int i = 0; i < 8; ++i) {
    const float x = 1.5f + 2.4f * i;
    const float side = i % 2 ? 1.f : -1.f;
    const float depth = 0.25f + 0.1f * (i % 3);
    const float height = 0.6f + 0.25f * (i % 4);
    const Eigen::Vector3f lo(x, side > 0 ? 1.2f - depth : -1.2f, 0.f);
    scene->AddBox(lo, lo + Eigen::Vector3f(0.8f, depth, height), MakeTexture(rng, 0.5f, 0.35f, 0.5f));
  }
  scene->AddCylinder({{9.f, 0.9f}, 0.15f, 0.f, 2.6f, MakeTexture(rng, 0.4f, 0.3f, 0.3f)});
  scene->AddCylinder({{15.f, -0.9f}, 0.15f, 0.f, 2.6f, MakeTexture(rng, 0.6f, 0.3f, 0.3f)});
}

// A 6 x 5 x 3 m room walked around while looking at its middle, as a person films a room: a table
// with objects in the middle and a floor-to-ceiling pillar between the path and the table sweep
// through the view with strong parallax against the walls 3-5 m behind them; the walls are
// weakly textured (plaster, a plain ceiling) apart from one brick and one flagstone wall.
void OrbitRoom(std::mt19937& rng, Scene* scene) {
  scene->AddRoom({-3, -2.5f, 0}, {3, 2.5f, 3},
                 {MakeTexture(rng, 0.5f, 0.3f, 1.0f, 0.45f), MakeTexture(rng, 0.75f, 0.14f, 2.5f, 0.f, 0.75f),
                  MakeTexture(rng, 0.55f, 0.3f, 0.6f, 0.f, 0.3f), MakeTexture(rng, 0.45f, 0.3f, 1.4f, 0.6f),
                  MakeTexture(rng, 0.4f, 0.3f, 0.8f, 0.25f), MakeTexture(rng, 0.8f, 0.08f, 3.0f, 0.f, 0.8f)});
  scene->AddBox({-0.6f, -0.4f, 0.f}, {0.6f, 0.4f, 0.75f}, MakeTexture(rng, 0.6f, 0.3f, 0.5f, 0.f, 0.2f));  // Table.
  scene->AddBox({-0.35f, -0.2f, 0.75f}, {-0.1f, 0.05f, 1.f}, MakeTexture(rng, 0.35f, 0.4f, 0.15f, 0.08f));
  scene->AddBox({0.15f, 0.05f, 0.75f}, {0.4f, 0.25f, 0.85f}, MakeTexture(rng, 0.7f, 0.3f, 0.2f));
  scene->AddCylinder({{0.1f, -0.2f}, 0.07f, 0.75f, 1.0f, MakeTexture(rng, 0.4f, 0.35f, 0.1f)});
  scene->AddCylinder({{1.2f, 0.55f}, 0.15f, 0.f, 3.f, MakeTexture(rng, 0.6f, 0.25f, 0.4f)});  // Pillar.
  scene->AddBox({-2.95f, -1.0f, 0.f}, {-2.2f, 1.0f, 0.8f}, MakeTexture(rng, 0.45f, 0.3f, 0.3f, 0.12f));  // Sofa.
  scene->AddBox({0.4f, 2.05f, 0.f}, {1.8f, 2.45f, 2.0f}, MakeTexture(rng, 0.5f, 0.35f, 0.3f, 0.35f));    // Shelf.
  scene->AddBox({1.9f, -2.45f, 0.f}, {2.5f, -1.85f, 0.6f}, MakeTexture(rng, 0.55f, 0.35f, 0.25f, 0.2f)); // Crates.
  scene->AddBox({-2.6f, 1.95f, 0.f}, {-1.6f, 2.45f, 1.1f}, MakeTexture(rng, 0.4f, 0.3f, 0.5f));          // Cabinet.
  scene->AddCylinder({{-2.3f, -1.9f}, 0.3f, 0.f, 0.9f, MakeTexture(rng, 0.5f, 0.3f, 0.3f)});             // Barrel.
}

// A ring corridor around a building block, 3 m wide and 2.8 m high: the inside of a 36 x 20 m
// room with a 30 x 14 m block in its middle. Plain walls; cabinets, panels and doors of their own
// sizes and textures stand along both walls every 1.5-3.5 m, and floor and ceiling change every
// few metres, so that places along the 98 m ring look different from each other.
void BlockRing(std::mt19937& rng, Scene* scene) {
  scene->AddRoom({-18, -10, 0}, {18, 10, 2.8f},
                 {MakeTexture(rng, 0.6f, 0.2f, 1.1f, 0.f, 0.7f), MakeTexture(rng, 0.55f, 0.2f, 0.9f, 0.f, 0.7f),
                  MakeTexture(rng, 0.6f, 0.2f, 1.3f, 0.f, 0.7f), MakeTexture(rng, 0.6f, 0.2f, 1.0f, 0.f, 0.7f),
                  MakeTexture(rng, 0.4f, 0.3f, 0.9f, 0.6f, 0.3f), MakeTexture(rng, 0.75f, 0.1f, 1.6f, 0.f, 0.8f)});
  scene->AddBox({-15, -7, 0}, {15, 7, 2.8f}, MakeTexture(rng, 0.6f, 0.2f, 1.0f, 0.f, 0.7f));
  std::uniform_real_distribution<float> u(0.f, 1.f);
  // Along each wall (x or y, its coordinate, the side the corridor is on, its extent).
  struct Wall {
    int axis;  // 0: the wall runs along x; 1: along y.
    float at, into, from, to;
  };
  const Wall walls[] = {{0, -10, 1, -18, 18}, {0, 10, -1, -18, 18}, {1, -18, 1, -10, 10}, {1, 18, -1, -10, 10},
                        {0, -7, -1, -15, 15},  {0, 7, 1, -15, 15},    {1, -15, -1, -7, 7},  {1, 15, 1, -7, 7}};
  for (const Wall& w : walls) {
    for (float along = w.from + 0.5f + 2.f * u(rng); along < w.to - 1.5f; along += 1.5f + 2.f * u(rng)) {
      const float width = 0.5f + 1.1f * u(rng), depth = 0.04f + 0.36f * u(rng), height = 0.7f + 1.9f * u(rng);
      const float a0 = along, a1 = std::min(along + width, w.to - 0.3f);
      const float d0 = w.at, d1 = w.at + w.into * depth;
      Eigen::Vector3f lo, hi;
      lo[w.axis] = a0, hi[w.axis] = a1;
      lo[1 - w.axis] = std::min(d0, d1), hi[1 - w.axis] = std::max(d0, d1);
      lo.z() = 0.f, hi.z() = height;
      // A texture's numbers are drawn last to first, as the scenes were first rendered.
      const float lines = u(rng) < 0.4f ? 0.1f + 0.4f * u(rng) : 0.f;
      const float scale = 0.2f + 0.8f * u(rng), contrast = 0.2f + 0.2f * u(rng), base = 0.3f + 0.4f * u(rng);
      scene->AddBox(lo, hi, MakeTexture(rng, base, contrast, scale, lines));
      along = a1;
    }
  }
  // Floor and ceiling in stretches of 1.5-3.5 m, each with a texture of its own (one texture over
  // the whole floor would repeat along the ring with its tile's period).
  struct Corridor {
    int axis;  // The axis it runs along.
    float from, to, side_lo, side_hi;
  };
  const Corridor corridors[] = {{0, -18, 18, -10, -7}, {0, -18, 18, 7, 10}, {1, -7, 7, -18, -15}, {1, -7, 7, 15, 18}};
  for (const Corridor& c : corridors) {
    for (float along = c.from; along < c.to - 0.01f;) {
      const float next = std::min(c.to, along + 1.5f + 2.f * u(rng));
      for (const bool ceiling : {false, true}) {
        Eigen::Vector3f lo, hi;
        lo[c.axis] = along, hi[c.axis] = next;
        lo[1 - c.axis] = c.side_lo, hi[1 - c.axis] = c.side_hi;
        lo.z() = ceiling ? 2.79f : 0.f, hi.z() = ceiling ? 2.8f : 0.01f;
        if (ceiling) {
          const float scale = 0.5f + u(rng), contrast = 0.1f + 0.1f * u(rng), base = 0.65f + 0.2f * u(rng);
          scene->AddBox(lo, hi, MakeTexture(rng, base, contrast, scale, 0.f, 0.5f));
        } else {
          const float lines = u(rng) < 0.5f ? 0.3f + 0.5f * u(rng) : 0.f;
          const float scale = 0.3f + 0.7f * u(rng), contrast = 0.2f + 0.15f * u(rng), base = 0.3f + 0.3f * u(rng);
          scene->AddBox(lo, hi, MakeTexture(rng, base, contrast, scale, lines));
        }
      }
      along = next;
    }
  }
}

// The centre line of BlockRing's corridor, a 21 x 13 m rectangle with corners rounded to 1 m, at
// arc length s (metres, counter-clockwise from the middle of the -y side).
Eigen::Vector2d AlongBlockRing(double s) {
  constexpr double kA = 16.5, kB = 8.5, kR = 1.0;
  const double sx = 2 * (kA - kR), sy = 2 * (kB - kR), arc = 0.5 * M_PI * kR;
  const double length = 2 * (sx + sy) + 4 * arc;
  s = std::fmod(std::fmod(s, length) + length, length);
  // Sides in order: -y (going +x), +x (going +y), +y (going -x), -x (going -y), each followed by
  // its corner; the first side starts at its middle.
  const double sides[4] = {sx, sy, sx, sy};
  const Eigen::Vector2d dirs[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  Eigen::Vector2d p(0.0, -kB);
  double left = s;
  for (int k = 0; k < 5; ++k) {
    const int side = k % 4;
    const double straight = k == 0 ? 0.5 * sides[0] : k == 4 ? 0.5 * sides[0] : sides[side];
    if (left <= straight) return p + left * dirs[side];
    p += straight * dirs[side];
    left -= straight;
    if (k == 4) break;
    if (left <= arc) {
      const Eigen::Vector2d inward = dirs[(side + 1) % 4];
      const double angle = left / kR;
      return p + kR * std::sin(angle) * dirs[side] + kR * (1 - std::cos(angle)) * inward;
    }
    p += kR * (dirs[side] + dirs[(side + 1) % 4]);
    left -= arc;
  }
  return p;
}

// Two identical halves of a corridor, each 10 m long and closed by a partition with a door
// (perceptual aliasing): the walls, floor and ceiling repeat every 10 m (their textures' periods
// divide it) and the same furniture stands at the same places in both halves.
void TwinCorridor(std::mt19937& rng, Scene* scene) {
  scene->AddRoom({0, -1.5f, 0}, {21, 1.5f, 2.8f},
                 {MakeTexture(rng, 0.5f, 0.3f, 1.0f), MakeTexture(rng, 0.55f, 0.3f, 1.0f),
                  MakeTexture(rng, 0.5f, 0.35f, 1.25f, 0.f, 0.3f), MakeTexture(rng, 0.55f, 0.35f, 1.25f, 1.25f),
                  MakeTexture(rng, 0.4f, 0.3f, 1.0f, 0.5f), MakeTexture(rng, 0.7f, 0.25f, 1.25f, 0.f, 0.4f)});
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>> boxes;
  std::vector<Texture> textures;
  for (int i = 0; i < 6; ++i) {
    const float x = 0.5f + 1.5f * i + 0.5f * u(rng), side = i % 2 ? 1.f : -1.f;
    const float depth = 0.2f + 0.3f * u(rng), height = 0.6f + 1.6f * u(rng), width = 0.5f + 0.6f * u(rng);
    const Eigen::Vector3f lo(x, side > 0 ? 1.5f - depth : -1.5f, 0.f);
    boxes.emplace_back(lo, lo + Eigen::Vector3f(width, depth, height));
    const float scale = 0.3f + 0.4f * u(rng), base = 0.3f + 0.4f * u(rng);  // Last to first.
    textures.push_back(MakeTexture(rng, base, 0.3f, scale));
  }
  // A partition with a door (1 m wide, 2.1 m high) at the end of each half.
  const Texture partition = MakeTexture(rng, 0.5f, 0.3f, 1.0f);
  boxes.emplace_back(Eigen::Vector3f(9.8f, -1.5f, 0.f), Eigen::Vector3f(10.f, -0.5f, 2.8f));
  boxes.emplace_back(Eigen::Vector3f(9.8f, 0.5f, 0.f), Eigen::Vector3f(10.f, 1.5f, 2.8f));
  boxes.emplace_back(Eigen::Vector3f(9.8f, -0.5f, 2.1f), Eigen::Vector3f(10.f, 0.5f, 2.8f));
  for (int i = 0; i < 3; ++i) textures.push_back(partition);
  for (const float offset : {0.f, 10.f})
    for (size_t i = 0; i < boxes.size(); ++i)
      scene->AddBox(boxes[i].first + Eigen::Vector3f(offset, 0, 0), boxes[i].second + Eigen::Vector3f(offset, 0, 0),
                    textures[i]);
}

// Smooth there-and-back profile: 0 -> 1 -> 0 over tau in [0, 1] with zero speed at the ends.
double ThereAndBack(double tau) { return 0.5 - 0.5 * std::cos(kTwoPi * tau); }

}  // namespace

std::vector<std::string> SceneNames() {
  return {"loop", "shake", "forward", "rotation", "exposure", "orbit", "pan", "block", "twins", "handheld", "uturn", "swing"};
}

std::string SceneNameList(const std::string& separator, const std::string& last) {
  const std::vector<std::string> names = SceneNames();
  std::string list = names.front();
  for (size_t i = 1; i < names.size(); ++i) list += (i + 1 == names.size() ? last : separator) + names[i];
  return list;
}

int DefaultFrames(const std::string& scene) {
  if (scene == "loop" || scene == "exposure" || scene == "orbit" || scene == "uturn" || scene == "swing") return 600;
  if (scene == "forward") return 400;
  if (scene == "block") return 1200;
  if (scene == "twins") return 340;
  return 300;
}

void SynthOptions::Validate() const {
  const auto names = SceneNames();
  if (std::find(names.begin(), names.end(), scene) == names.end())
    throw InputError("--scene: unknown scene '" + scene + "' (expected " + SceneNameList(", ", " or ") + ")");
  if (frames < 0 || frames == 1 || frames > 100000) throw InputError("--frames must be 0 (default) or in 2..100000");
  if (width < 64 || height < 48 || width > 4096 || height > 4096)
    throw InputError("--width/--height must be within 64x48 .. 4096x4096");
  if (!(rate_hz > 0)) throw InputError("--rate must be positive");
  if (!(noise_sigma >= 0 && noise_sigma <= 50)) throw InputError("--noise must be within 0..50 grey levels");
  if (!(vignette >= 0 && vignette <= 0.8)) throw InputError("--vignette must be within 0..0.8");
  if (!(blur_sigma >= 0 && blur_sigma <= 10)) throw InputError("--blur must be within 0..10 pixels");
  // The rows are read out within the frame interval.
  if (!ReadoutFits(line_delay_us, height, 1e6 / rate_hz))
    throw InputError("--rolling-shutter must be within 0.." + std::to_string(1e6 / rate_hz / height) +
                     " us per row (the readout of all rows within one frame interval)");
  ParseDefects(defects);
}

SE3d LookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - position).normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x, y, z;
  return SE3d(SO3d(R), position);
}

namespace {

// The hand-held scene's roll about the optical axis at time t_s.
SO3d HandRoll(double t_s) {
  const double roll = std::min(1.0, t_s) * 0.2 * std::sin(kTwoPi * 0.45 * t_s + 2.0);
  return SO3d::Exp(Eigen::Vector3d(0.0, 0.0, roll));
}

}  // namespace

std::vector<SE3d> SynthSequence::RowPoses(size_t i) const {
  std::vector<SE3d> rows(camera.height);
  for (int v = 0; v < camera.height; ++v) rows[v] = pose_at(static_cast<double>(i) + v * line_delay_frames);
  return rows;
}

CameraCalibration SynthSequence::Calibration() const {
  if (lens) return lens->camera();
  return {CameraModel::kPinhole, camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy, {}};
}

SynthSequence MakeSequence(const SynthOptions& options) {
  options.Validate();
  SynthSequence seq;
  std::mt19937 rng(options.seed * 2654435761u + 12345u);
  const std::string& name = options.scene;
  const int n = options.frames > 0 ? options.frames : DefaultFrames(name);
  seq.camera.width = options.width;
  seq.camera.height = options.height;
  seq.camera.fx = seq.camera.fy = 0.6 * options.width;
  seq.camera.cx = 0.5 * (options.width - 1);
  seq.camera.cy = 0.5 * (options.height - 1);
  if (options.model != CameraModel::kPinhole) {
    CameraCalibration lens = seq.Calibration();
    lens.model = options.model;
    lens.distortion = TypicalDistortion(options.model);
    lens.Validate("--model");
    seq.lens = std::make_shared<const LensRays>(lens);
  }

  if (name == "forward" || name == "uturn") {
    Corridor(rng, &seq.scene);
  } else if (name == "orbit") {
    OrbitRoom(rng, &seq.scene);
  } else if (name == "twins") {
    TwinCorridor(rng, &seq.scene);
  } else if (name == "block") {
    BlockRing(rng, &seq.scene);
    seq.scene.TurnTextures();
  } else {
    FurnishedRoom(rng, &seq.scene);
  }
  if (options.turned_textures) seq.scene.TurnTextures();
  if (options.plain_pillars) seq.scene.PlainPillars();
  const Jitter jitter(rng);
  const Jitter look_jitter(rng);

  // The camera at frame position f (frame i at f = i; a rolling shutter's row between frames).
  const double rate_hz = options.rate_hz;
  seq.pose_at = [name, n, rate_hz, jitter, look_jitter](double f) {
    const double t_s = f / rate_hz;
    const double tau = n > 1 ? f / (n - 1) : 0.0;
    Eigen::Vector3d position, target;
    if (name == "loop" || name == "exposure") {
      // An ellipse at a steady pace, looking outwards and a little ahead: two laps in the default
      // length, more in longer sequences (20 in 6000 frames).
      const double a = 2.0 * kTwoPi * f / (DefaultFrames(name) - 1);
      position = Eigen::Vector3d(1.9 * std::cos(a), 1.3 * std::sin(a), 1.5) + 0.03 * jitter.At(t_s);
      const double look = a + 0.35;
      target = position + Eigen::Vector3d(std::cos(look), std::sin(look), -0.12) + 0.04 * look_jitter.At(t_s);
    } else if (name == "orbit") {
      // Two laps counter-clockwise around the middle at ~0.75 m/s, looking at it from 1.45 m
      // height: walking bob (1.8 Hz steps), side sway, hand jitter and yaw swings of +-10 deg.
      const double a = 2.0 * kTwoPi * tau - 0.5 * M_PI;
      const Eigen::Vector3d radial(std::cos(a), std::sin(a), 0.0);
      position = Eigen::Vector3d(2.0 * radial.x(), 1.45 * radial.y(), 1.45) +
                 Eigen::Vector3d(0, 0, 0.02 * std::sin(kTwoPi * 1.8 * t_s)) +
                 0.02 * std::sin(kTwoPi * 0.9 * t_s) * radial + 0.015 * jitter.At(t_s);
      const double sway = 0.17 * std::sin(kTwoPi * 0.27 * t_s + 0.4);
      const Eigen::Vector3d tangent(-std::sin(a), std::cos(a), 0.0);
      target = Eigen::Vector3d(0.0, 0.0, 0.95) + 1.6 * sway * tangent + 0.12 * look_jitter.At(t_s);
    } else if (name == "twins") {
      // Down the corridor at 1 m/s from x = 0.8 m, looking ahead: the second half shows again, 10 m
      // on, what the first showed.
      position = Eigen::Vector3d(0.8 + t_s, 0.05 * std::sin(kTwoPi * 0.15 * t_s), 1.4) + 0.02 * jitter.At(t_s);
      target = position + Eigen::Vector3d(1.0, 0.1 * std::sin(kTwoPi * 0.11 * t_s), -0.08) + 0.03 * look_jitter.At(t_s);
    } else if (name == "block") {
      // Walking around the ring at 1.5 m/s, looking at the centre line 2 m ahead: a lap takes 44 s,
      // the default length goes on for a fifth of a lap past the start.
      const double s = 2.0 * t_s;
      const Eigen::Vector2d here = AlongBlockRing(s), ahead = AlongBlockRing(s + 2.0);
      position = Eigen::Vector3d(here.x(), here.y(), 1.5) + Eigen::Vector3d(0.1, 0.1, 0.04).cwiseProduct(jitter.At(t_s));
      target = Eigen::Vector3d(ahead.x(), ahead.y(), 1.4) + 0.1 * look_jitter.At(t_s);
    } else if (name == "shake") {
      // Side to side and up and down in front of the +y wall, about 0.5 m, looking at it.
      position = Eigen::Vector3d(0.25 * std::sin(kTwoPi * 0.23 * t_s) + 0.05 * jitter.At(t_s).x(),
                                 -0.3 + 0.08 * std::sin(kTwoPi * 0.11 * t_s),
                                 1.4 + 0.15 * std::sin(kTwoPi * 0.37 * t_s + 1.0) + 0.03 * jitter.At(t_s).z());
      target = Eigen::Vector3d(0.4 * std::sin(kTwoPi * 0.17 * t_s + 0.5), 3.0, 1.3) + 0.25 * look_jitter.At(t_s);
    } else if (name == "forward") {
      // 12 m down the corridor and back, reversing with the same heading.
      const double x = 0.5 + 12.0 * ThereAndBack(tau);
      position = Eigen::Vector3d(x, 0.15 * std::sin(kTwoPi * 0.2 * t_s), 1.4) + 0.02 * jitter.At(t_s);
      target = position + Eigen::Vector3d(1.0, 0.05 * std::sin(kTwoPi * 0.13 * t_s), -0.05) + 0.03 * look_jitter.At(t_s);
    } else if (name == "uturn") {
      // Out along y = -0.45 m to x = 11 m facing +x, a U-turn there (the heading turns by 180 deg
      // over 4.5 s while the camera crosses to y = +0.45 m, slowing to a stop at the far end) and
      // back along the other side facing -x; the pace peaks at ~1.1 m/s mid-corridor.
      const double x = 0.5 + 10.5 * ThereAndBack(tau);
      const double turn = SmoothStep(0.425, 0.575, tau);
      const double yaw = M_PI * turn;
      position = Eigen::Vector3d(x, -0.45 * std::cos(M_PI * turn), 1.4 + 0.02 * std::sin(kTwoPi * 1.7 * t_s)) +
                 0.02 * jitter.At(t_s);
      target = position + Eigen::Vector3d(std::cos(yaw), std::sin(yaw), -0.06) + 0.03 * look_jitter.At(t_s);
    } else if (name == "swing") {
      // Two laps of a 5.0 x 3.4 m ellipse, facing along the path and 0.45 rad outwards (the
      // walls and the furniture in front), with a walking bob.
      const double a = 2.0 * kTwoPi * tau;
      position = Eigen::Vector3d(2.5 * std::cos(a), 1.7 * std::sin(a), 1.5 + 0.02 * std::sin(kTwoPi * 1.8 * t_s)) +
                 0.02 * jitter.At(t_s);
      const Eigen::Vector3d ahead(-2.5 * std::sin(a), 1.7 * std::cos(a), 0.0);
      const double heading = std::atan2(ahead.y(), ahead.x()) - 0.45;
      target = position + Eigen::Vector3d(std::cos(heading), std::sin(heading), -0.1) + 0.04 * look_jitter.At(t_s);
    } else if (name == "pan") {
      // Hand-held panning from the first frame: 1.3 m in front of the +y wall, yaw swings of
      // +-30 deg (0.3 Hz) and a few centimetres of hand motion, so the first 5 s see mostly one
      // plane under almost pure rotation; then a slow walk back (0.25 m/s) still panning.
      const double back = 0.25 * std::max(0.0, t_s - 5.0);
      position = Eigen::Vector3d(0.0, 1.7 - back, 1.5) + 0.03 * jitter.At(t_s);
      const double yaw = 0.5 * M_PI + 0.52 * std::sin(kTwoPi * 0.3 * t_s);
      const double pitch = 0.08 + 0.1 * std::sin(kTwoPi * 0.17 * t_s);
      target = position + Eigen::Vector3d(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), std::sin(pitch)) +
               0.03 * look_jitter.At(t_s);
    } else if (name == "handheld") {
      // A phone held out in the furnished room and turned about, as people film: yaw swings of
      // +-34 deg (0.35 Hz), pitch +-14 deg (0.5 Hz) and roll +-11 deg (HandRoll) with hand tremor,
      // while the body sways by a few decimetres: the turn peaks near 90 deg/s. The swings grow
      // over the first second.
      const double ramp = std::min(1.0, t_s);
      position = Eigen::Vector3d(0.3 * std::sin(kTwoPi * 0.1 * t_s), -0.5 + 0.2 * std::sin(kTwoPi * 0.13 * t_s + 1.0),
                                 1.5 + 0.05 * std::sin(kTwoPi * 0.4 * t_s)) +
                 0.03 * jitter.At(t_s);
      const double yaw = 0.6 + ramp * 0.6 * std::sin(kTwoPi * 0.35 * t_s);
      const double pitch = -0.05 + ramp * 0.25 * std::sin(kTwoPi * 0.5 * t_s + 0.7);
      target = position + Eigen::Vector3d(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), std::sin(pitch)) +
               0.02 * look_jitter.At(t_s);
    } else {  // rotation
      // A small circle (10 cm) with large yaw (+-70 deg) and pitch (+-20 deg) swings.
      const double a = kTwoPi * 0.25 * t_s;
      position = Eigen::Vector3d(0.1 * std::cos(a), 0.1 * std::sin(a), 1.5);
      const double ramp = std::min(1.0, t_s / 2.0);  // Swings grow over the first 2 s.
      const double yaw = ramp * 1.22 * std::sin(kTwoPi * 0.12 * t_s) + 0.5;
      const double pitch = ramp * 0.35 * std::sin(kTwoPi * 0.21 * t_s + 0.7);
      target = position + Eigen::Vector3d(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), std::sin(pitch));
    }
    SE3d pose = LookAt(position, target);
    if (name == "handheld") pose = pose * SE3d(HandRoll(t_s), Eigen::Vector3d::Zero());
    return pose;
  };
  seq.line_delay_frames = options.line_delay_us * 1e-6 * options.rate_hz;
  for (int i = 0; i < n; ++i) {
    const double t_s = i / options.rate_hz;
    seq.world_from_cam.push_back(seq.pose_at(i));
    seq.t_ns.push_back(kStartNs + static_cast<int64_t>(std::llround(t_s * 1e9)));
    Photometry p;
    if (name == "exposure") {
      p.exposure_ms = 10.0 * (0.75 + 0.25 * std::sin(kTwoPi * 0.09 * t_s));
      p.gain = static_cast<float>(1.0 + 0.15 * std::sin(kTwoPi * 0.05 * t_s + 1.0));
      p.offset = static_cast<float>(8.0 * std::sin(kTwoPi * 0.07 * t_s));
    } else if (name == "swing") {
      p.exposure_ms = 7.5 * (1.0 + 0.4 * std::sin(kTwoPi * 0.08 * t_s));
      p.gain = static_cast<float>(1.0 + 0.1 * std::sin(kTwoPi * 0.045 * t_s + 0.5));
    }
    seq.photometry.push_back(p);
  }
  return seq;
}

}  // namespace dsm::synth
