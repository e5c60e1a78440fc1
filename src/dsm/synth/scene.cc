// SPDX-License-Identifier: MIT
#include "dsm/synth/scene.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "dsm/util/check.h"

namespace dsm::synth {

void Scene::AddBox(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Texture& texture) {
  DSM_CHECK((hi - lo).minCoeff() > 0.f, "empty box");
  Box box{lo, hi, {}, false};
  for (int f = 0; f < 6; ++f) {
    box.faces[f] = texture;
    box.faces[f].seed = texture.seed + 7919u * f;
  }
  boxes_.push_back(box);
}

void Scene::AddRoom(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const std::array<Texture, 6>& faces) {
  DSM_CHECK((hi - lo).minCoeff() > 0.f, "empty room");
  boxes_.push_back({lo, hi, faces, true});
}

void Scene::AddCylinder(const Cylinder& c) { cylinders_.push_back(c); }

void Scene::TurnTextures() {
  for (Box& box : boxes_)
    for (Texture& face : box.faces) face.turned = true;
  for (Cylinder& cylinder : cylinders_) cylinder.texture.turned = true;
}

void Scene::PlainPillars(float min_height_m) {
  for (Cylinder& cylinder : cylinders_)
    if (cylinder.z_min <= 0.f && cylinder.z_max >= min_height_m) {
      cylinder.texture.contrast *= 0.1f;
      cylinder.texture.line_spacing_m = 0.f;
    }
}

Scene::Subset Scene::All() const {
  Subset all;
  for (size_t i = 0; i < boxes_.size(); ++i) all.boxes.push_back(static_cast<int>(i));
  for (size_t i = 0; i < cylinders_.size(); ++i) all.cylinders.push_back(static_cast<int>(i));
  return all;
}

namespace {

// True when all corners of the box [lo, hi] are strictly outside one side plane of the cone.
bool OutsideCone(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Eigen::Vector3f& origin,
                 const std::array<Eigen::Vector3f, 4>& normals) {
  for (const Eigen::Vector3f& n : normals) {
    bool all_outside = true;
    for (int c = 0; c < 8 && all_outside; ++c) {
      const Eigen::Vector3f corner(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z());
      all_outside = n.dot(corner - origin) < 0.f;
    }
    if (all_outside) return true;
  }
  return false;
}

}  // namespace

Scene::Subset Scene::InCone(const Eigen::Vector3f& origin, const std::array<Eigen::Vector3f, 4>& corners) const {
  // Side plane k contains corners k and k+1; its normal points into the cone.
  std::array<Eigen::Vector3f, 4> normals;
  const Eigen::Vector3f centre = corners[0] + corners[1] + corners[2] + corners[3];
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector3f n = corners[k].cross(corners[(k + 1) % 4]);
    if (n.dot(centre) < 0.f) n = -n;
    normals[k] = n;
  }
  Subset subset;
  for (size_t i = 0; i < boxes_.size(); ++i) {
    const Box& b = boxes_[i];
    if (b.inside || !OutsideCone(b.lo, b.hi, origin, normals)) subset.boxes.push_back(static_cast<int>(i));
  }
  for (size_t i = 0; i < cylinders_.size(); ++i) {
    const Cylinder& c = cylinders_[i];
    const Eigen::Vector3f lo(c.centre.x() - c.radius, c.centre.y() - c.radius, c.z_min);
    const Eigen::Vector3f hi(c.centre.x() + c.radius, c.centre.y() + c.radius, c.z_max);
    if (!OutsideCone(lo, hi, origin, normals)) subset.cylinders.push_back(static_cast<int>(i));
  }
  // The directions that leave a convex room through one face form a convex cone: if the four
  // corner rays leave through the same face, every ray between them does.
  if (subset.boxes.size() == 1 && subset.cylinders.empty() && boxes_[subset.boxes[0]].inside) {
    const Box& b = boxes_[subset.boxes[0]];
    int face = -1;
    for (const Eigen::Vector3f& d : corners) {
      float t_exit = std::numeric_limits<float>::infinity();
      int f = -1;
      for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.f) continue;
        const float t = ((d[a] > 0.f ? b.hi[a] : b.lo[a]) - origin[a]) / d[a];
        if (t < t_exit) t_exit = t, f = 2 * a + (d[a] > 0.f ? 1 : 0);
      }
      if (face == -1) face = f;
      if (f != face) {
        face = -2;
        break;
      }
    }
    if (face >= 0) subset.single_face = face;
  }
  return subset;
}

bool Scene::Intersect(const Eigen::Vector3f& o, const Eigen::Vector3f& dir, const Subset& subset, Hit* hit) const {
  constexpr float kMin = 1e-4f;
  float best = std::numeric_limits<float>::infinity();
  if (subset.single_face >= 0) {
    const Box& b = boxes_[subset.boxes[0]];
    const int axis = subset.single_face / 2;
    const bool plus = subset.single_face % 2;
    const float s = ((plus ? b.hi[axis] : b.lo[axis]) - o[axis]) / dir[axis];
    if (!(s > kMin)) return false;
    const Eigen::Vector3f p = o + s * dir;
    const int ua = axis == 0 ? 1 : 0, va = axis == 2 ? 1 : 2;
    hit->distance = s;
    hit->u = p[ua] - b.lo[ua];
    hit->v = p[va] - b.lo[va];
    hit->cos_incidence = std::fabs(dir[axis]);
    hit->texture = &b.faces[subset.single_face];
    return true;
  }
  const Eigen::Vector3f inv(1.f / dir.x(), 1.f / dir.y(), 1.f / dir.z());
  for (const int bi : subset.boxes) {
    const Box& b = boxes_[bi];
    // Slab test: the ray is inside slab a for s in [min(t1, t2), max(t1, t2)].
    float t_enter = -std::numeric_limits<float>::infinity(), t_exit = std::numeric_limits<float>::infinity();
    int enter_axis = 0, exit_axis = 0;
    for (int a = 0; a < 3; ++a) {
      const float t1 = (b.lo[a] - o[a]) * inv[a], t2 = (b.hi[a] - o[a]) * inv[a];
      const float near = t1 < t2 ? t1 : t2, far = t1 < t2 ? t2 : t1;
      if (near > t_enter) t_enter = near, enter_axis = a;
      if (far < t_exit) t_exit = far, exit_axis = a;
    }
    if (t_enter > t_exit || t_enter >= best) continue;
    const float s = b.inside ? t_exit : t_enter;
    const int axis = b.inside ? exit_axis : enter_axis;
    if (s <= kMin || s >= best) continue;
    // Face hit: on the + side when (inside and moving +) or (outside and moving -).
    const bool plus = b.inside == (dir[axis] > 0.f);
    const Eigen::Vector3f p = o + s * dir;
    const int ua = axis == 0 ? 1 : 0, va = axis == 2 ? 1 : 2;
    best = s;
    hit->distance = s;
    hit->u = p[ua] - b.lo[ua];
    hit->v = p[va] - b.lo[va];
    hit->cos_incidence = std::fabs(dir[axis]);
    hit->texture = &b.faces[2 * axis + (plus ? 1 : 0)];
  }
  for (const int ci : subset.cylinders) {
    const Cylinder& c = cylinders_[ci];
    // |(o + s d)_xy - centre|^2 = r^2  ->  A s^2 + 2 B s + C = 0
    const float px = o.x() - c.centre.x(), py = o.y() - c.centre.y();
    const float A = dir.x() * dir.x() + dir.y() * dir.y();
    if (A < 1e-12f) continue;
    const float B = px * dir.x() + py * dir.y();
    const float C = px * px + py * py - c.radius * c.radius;
    const float disc = B * B - A * C;
    if (disc < 0.f) continue;
    const float s = (-B - std::sqrt(disc)) / A;  // Entry point: the outer surface.
    if (s <= kMin || s >= best) continue;
    const float z = o.z() + s * dir.z();
    if (z < c.z_min || z > c.z_max) continue;
    best = s;
    const float nx = (px + s * dir.x()) / c.radius, ny = (py + s * dir.y()) / c.radius;
    hit->distance = s;
    hit->u = std::atan2(ny, nx) * c.radius;
    hit->v = z;
    hit->cos_incidence = std::fabs(nx * dir.x() + ny * dir.y());
    hit->texture = &c.texture;
  }
  return best < std::numeric_limits<float>::infinity();
}

}  // namespace dsm::synth
