// SPDX-License-Identifier: MIT
#include "dsm/optimization/pose_graph.h"

#include <chrono>
#include <cmath>

#include <ceres/ceres.h>

#include "dsm/util/check.h"

namespace dsm {

namespace {

struct Node {
  double q[4];  // Eigen order x, y, z, w.
  double t[3];
  double log_scale;
};

// The residual of one edge (see the header).
struct EdgeResidual {
  Sim3d measured;  // i_from_j
  double weight;

  template <typename T>
  bool operator()(const T* qi, const T* ti, const T* si, const T* qj, const T* tj, const T* sj, T* r) const {
    using Quat = Eigen::Quaternion<T>;
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Quat> Qi(qi), Qj(qj);
    const Eigen::Map<const Vec3> Ti(ti), Tj(tj);
    // S_j S_i^-1 = (e^(sj - si), Qj Qi^-1, tj - e^(sj - si) Qj Qi^-1 ti).
    const Quat q_ji = Qj * Qi.conjugate();
    const T ratio = ceres::exp(sj[0] - si[0]);
    const Vec3 t_ji = Tj - ratio * (q_ji * Ti);
    // E = measured (S_j S_i^-1).
    const Quat qm = measured.So3().Quaternion().template cast<T>();
    const Vec3 tm = measured.Translation().template cast<T>();
    const T sm = T(measured.Scale());
    const Quat q_e = qm * q_ji;
    const Vec3 t_e = sm * (qm * t_ji) + tm;
    const T sign = q_e.w() < T(0) ? T(-2) : T(2);
    for (int k = 0; k < 3; ++k) r[k] = T(weight) * t_e[k];
    r[3] = T(weight) * sign * q_e.x();
    r[4] = T(weight) * sign * q_e.y();
    r[5] = T(weight) * sign * q_e.z();
    r[6] = T(weight) * (T(std::log(measured.Scale())) + sj[0] - si[0]);
    return true;
  }
};

struct BrightnessResidual {
  BrightnessEdge edge;
  double sigma_a, sigma_b;

  template <typename T>
  bool operator()(const T* i, const T* j, T* r) const {
    r[0] = (j[0] - i[0] - T(edge.alpha)) / T(sigma_a);
    r[1] = (j[1] - T(std::exp(edge.alpha)) * i[1] - T(edge.beta)) / T(sigma_b);
    return true;
  }
};

}  // namespace

std::vector<Eigen::Vector2d> OptimizeBrightnessGraph(const std::vector<Eigen::Vector2d>& ab,
                                                     const std::vector<BrightnessEdge>& edges,
                                                     const std::vector<int>& fixed, double sigma_a, double sigma_b) {
  std::vector<Eigen::Vector2d> nodes = ab;
  ceres::Problem problem;
  for (const BrightnessEdge& e : edges) {
    DSM_CHECK(e.i >= 0 && e.i < static_cast<int>(nodes.size()) && e.j >= 0 && e.j < static_cast<int>(nodes.size()),
              "brightness edge between two of its nodes");
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<BrightnessResidual, 2, 2, 2>(new BrightnessResidual{e, sigma_a, sigma_b}), nullptr,
        nodes[e.i].data(), nodes[e.j].data());
  }
  for (int f : fixed)
    if (problem.HasParameterBlock(nodes[f].data())) problem.SetParameterBlockConstant(nodes[f].data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 20;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return nodes;
}

PoseGraphResult OptimizePoseGraph(const std::vector<Sim3d>& cam_from_world, const std::vector<PoseGraphEdge>& edges,
                                  const std::vector<int>& fixed, int max_iterations) {
  const auto start = std::chrono::steady_clock::now();
  const int n = static_cast<int>(cam_from_world.size());
  std::vector<Node> nodes(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Quaterniond q = cam_from_world[i].So3().Quaternion();
    nodes[i].q[0] = q.x(), nodes[i].q[1] = q.y(), nodes[i].q[2] = q.z(), nodes[i].q[3] = q.w();
    for (int k = 0; k < 3; ++k) nodes[i].t[k] = cam_from_world[i].Translation()[k];
    nodes[i].log_scale = std::log(cam_from_world[i].Scale());
  }
  ceres::Problem problem;
  for (const PoseGraphEdge& e : edges) {
    DSM_CHECK(e.i >= 0 && e.i < n && e.j >= 0 && e.j < n && e.i != e.j, "pose graph edge between two of its nodes");
    auto* cost = new ceres::AutoDiffCostFunction<EdgeResidual, 7, 4, 3, 1, 4, 3, 1>(new EdgeResidual{e.i_from_j, e.weight});
    Node& a = nodes[e.i];
    Node& b = nodes[e.j];
    problem.AddResidualBlock(cost, nullptr, a.q, a.t, &a.log_scale, b.q, b.t, &b.log_scale);
  }
  for (Node& node : nodes)
    if (problem.HasParameterBlock(node.q)) problem.SetManifold(node.q, new ceres::EigenQuaternionManifold);
  for (int f : fixed) {
    Node& node = nodes[f];
    if (!problem.HasParameterBlock(node.q)) continue;
    problem.SetParameterBlockConstant(node.q);
    problem.SetParameterBlockConstant(node.t);
    problem.SetParameterBlockConstant(&node.log_scale);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  PoseGraphResult result;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.iterations = static_cast<int>(summary.iterations.size());
  for (const Node& node : nodes) {
    const Eigen::Quaterniond q(node.q[3], node.q[0], node.q[1], node.q[2]);
    result.cam_from_world.emplace_back(std::exp(node.log_scale), SO3d::FromUnitQuaternion(q.normalized()),
                                       Eigen::Vector3d(node.t[0], node.t[1], node.t[2]));
  }
  result.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace dsm
