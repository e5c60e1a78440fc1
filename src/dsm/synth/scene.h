// SPDX-License-Identifier: MIT
// Textured geometry for the synthetic test world: axis-aligned boxes (seen from outside, or from
// inside as a room) and vertical cylinders, intersected by rays. World frame: z up, metres.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "dsm/synth/texture.h"

namespace dsm::synth {

// Faces in the order -x, +x, -y, +y, -z, +z.
struct Box {
  Eigen::Vector3f lo, hi;
  std::array<Texture, 6> faces;
  bool inside = false;  // A room: rays start inside and hit the walls from within.
};

// Vertical cylinder (outer surface), axis through (centre.x, centre.y), z in [z_min, z_max].
struct Cylinder {
  Eigen::Vector2f centre;
  float radius = 0.5f, z_min = 0.f, z_max = 1.f;
  Texture texture;
};

struct Hit {
  float distance = 0.f;       // Along the (unit) ray.
  float u = 0.f, v = 0.f;     // Surface coordinates in metres.
  float cos_incidence = 1.f;  // |cos| between the ray and the surface normal.
  const Texture* texture = nullptr;
};

class Scene {
 public:
  // A box whose six faces use `texture` with six different seeds.
  void AddBox(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Texture& texture);
  // The inside of a box: walls (-x, +x, -y, +y), floor and ceiling with their own textures.
  void AddRoom(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const std::array<Texture, 6>& faces);
  void AddCylinder(const Cylinder& cylinder);
  // Every texture of the scene read along turned axes (Texture::turned).
  void TurnTextures();
  // Every pillar (a cylinder from the floor up to at least `min_height_m`) plain: its texture keeps
  // a tenth of its contrast, like painted plaster, so points can be selected only along its
  // silhouette (against what is behind it).
  void PlainPillars(float min_height_m = 2.f);

  // The primitives a group of rays may hit: indices into the boxes and the cylinders.
  struct Subset {
    std::vector<int> boxes, cylinders;
    // When the subset is one room and every ray of the cone leaves it through the same face
    // (2 * axis + (1 on the + side)), the hit is a single ray-plane intersection.
    int single_face = -1;
  };
  Subset All() const;

  // The primitives that may intersect the cone of rays from `origin` between the unit directions
  // `corners` (in order around the cone): a box is left out when its 8 corners lie outside one of
  // the cone's side planes. Conservative: never leaves out a primitive that a ray in the cone hits.
  Subset InCone(const Eigen::Vector3f& origin, const std::array<Eigen::Vector3f, 4>& corners) const;

  // Nearest hit of the ray origin + s dir (|dir| = 1, s > 1e-4) among `subset`; false when none.
  bool Intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, const Subset& subset, Hit* hit) const;
  bool Intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, Hit* hit) const {
    return Intersect(origin, dir, All(), hit);
  }

  size_t NumPrimitives() const { return boxes_.size() + cylinders_.size(); }

 private:
  std::vector<Box> boxes_;
  std::vector<Cylinder> cylinders_;
};

}  // namespace dsm::synth
