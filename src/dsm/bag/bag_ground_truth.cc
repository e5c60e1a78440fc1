// SPDX-License-Identifier: MIT
#include "dsm/bag/bag_ground_truth.h"

#include <algorithm>
#include <map>
#include <set>
#include <utility>

#include "dsm/bag/messages.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

std::string FrameName(const std::string& frame) { return frame.empty() || frame[0] != '/' ? frame : frame.substr(1); }

std::string Where(const BagFile& bag, const std::string& topic, size_t index) {
  return bag.path().string() + " " + topic + " message " + std::to_string(index);
}

// Every pose in the messages of `topic`.
std::vector<StampedPose> ReadPoses(const BagFile& bag, const std::string& topic) {
  const std::string type = bag.TypeOf(topic);
  if (!IsPoseType(type)) {
    throw InputError(bag.path().string() + ": topic " + topic + " is " + type +
                     ", not a pose (PoseStamped, PoseWithCovarianceStamped, TransformStamped, Odometry, TFMessage)");
  }
  std::vector<StampedPose> poses;
  const size_t count = bag.LogTimes(topic).size();
  for (size_t i = 0; i < count; ++i) {
    const std::vector<uint8_t> bytes = bag.Read(topic, i);
    WireReader in(bytes.data(), bytes.size(), bag.WireOf(topic), Where(bag, topic, i));
    try {
      for (const StampedPose& p : DecodePoses(type, in)) poses.push_back(p);
    } catch (const InputError& e) {
      throw InputError(Where(bag, topic, i) + ": " + e.what());
    }
  }
  return poses;
}

// Stamp order; of poses with the same stamp the last one read.
Trajectory SortedTrajectory(std::vector<std::pair<int64_t, SE3d>> poses) {
  std::stable_sort(poses.begin(), poses.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Trajectory trajectory;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (i + 1 < poses.size() && poses[i + 1].first == poses[i].first) continue;
    trajectory.Add(poses[i].first, poses[i].second);
  }
  return trajectory;
}

// A link's pose at `t_ns` between the two samples around it (translation linear, rotation slerp);
// false outside the samples' span.
bool Interpolate(const Trajectory& link, int64_t t_ns, SE3d* pose) {
  const auto& stamps = link.stamps_ns;
  const auto upper = std::lower_bound(stamps.begin(), stamps.end(), t_ns);
  if (upper == stamps.end()) return false;
  const size_t b = static_cast<size_t>(upper - stamps.begin());
  if (*upper == t_ns) {
    *pose = link.poses[b];
    return true;
  }
  if (b == 0) return false;
  const double s = static_cast<double>(t_ns - stamps[b - 1]) / static_cast<double>(stamps[b] - stamps[b - 1]);
  const SE3d& p0 = link.poses[b - 1];
  const SE3d& p1 = link.poses[b];
  *pose = SE3d(p0.So3().Quaternion().slerp(s, p1.So3().Quaternion()),
               (1.0 - s) * p0.Translation() + s * p1.Translation());
  return true;
}

}  // namespace

Trajectory ReadPoseTopic(const BagFile& bag, const std::string& topic) {
  if (bag.TypeOf(topic) == "tf2_msgs/TFMessage") {
    throw InputError(bag.path().string() + ": topic " + topic +
                     " holds transforms between frames: name the two frames with --gt-frames PARENT CHILD");
  }
  std::vector<std::pair<int64_t, SE3d>> poses;
  for (const StampedPose& p : ReadPoses(bag, topic)) poses.emplace_back(p.stamp_ns, p.pose);
  if (poses.empty()) throw InputError(bag.path().string() + ": topic " + topic + " has no pose");
  return SortedTrajectory(std::move(poses));
}

Trajectory ReadTfChain(const BagFile& bag, const std::string& parent_frame, const std::string& child_frame,
                       const std::string& tf_topic) {
  // Each link child -> (parent, its poses over time); fixed links from /tf_static.
  struct Link {
    std::string parent;
    std::vector<std::pair<int64_t, SE3d>> samples;
    bool fixed = false;
  };
  std::map<std::string, Link> links;
  const auto add = [&](const std::string& topic, bool fixed) {
    for (const StampedPose& p : ReadPoses(bag, topic)) {
      Link& link = links[FrameName(p.child)];
      link.parent = FrameName(p.parent);
      link.fixed = fixed;
      link.samples.emplace_back(p.stamp_ns, p.pose);
    }
  };
  add(tf_topic, false);
  for (const BagTopic& t : bag.Topics()) {
    if (t.name == "/tf_static" && t.type == "tf2_msgs/TFMessage") add(t.name, true);
  }
  const std::string parent = FrameName(parent_frame);
  const std::string child = FrameName(child_frame);
  // The frames from `frame` up to the tree's root.
  const auto up = [&](std::string frame) {
    std::vector<std::string> path{frame};
    std::set<std::string> seen{frame};
    for (auto it = links.find(frame); it != links.end(); it = links.find(it->second.parent)) {
      if (!seen.insert(it->second.parent).second) break;  // A cycle: not a tree.
      path.push_back(it->second.parent);
    }
    return path;
  };
  const std::vector<std::string> from_child = up(child);
  const std::vector<std::string> from_parent = up(parent);
  const auto common = std::find_first_of(from_child.begin(), from_child.end(), from_parent.begin(), from_parent.end());
  if (common == from_child.end()) {
    std::string frames;
    for (const auto& [name, link] : links) frames += (frames.empty() ? "" : ", ") + link.parent + " -> " + name;
    throw InputError(bag.path().string() + ": no chain of transforms joins " + parent + " and " + child + " on " +
                     tf_topic + " and /tf_static (links: " + (frames.empty() ? std::string("none") : frames) + ")");
  }
  // The chain's links: up from the child to the common frame (forward), and up from the parent
  // to it (inverted).
  struct Step {
    Trajectory poses;
    bool fixed;
    bool inverted;
  };
  const auto steps_up = [&](const std::vector<std::string>& path, bool inverted) {
    std::vector<Step> steps;
    for (size_t i = 0; path[i] != *common; ++i) {
      const Link& link = links.at(path[i]);
      steps.push_back({SortedTrajectory(link.samples), link.fixed, inverted});
    }
    return steps;
  };
  // parent_from_child = (common_from_parent)^-1 * common_from_child: the parent's links upward,
  // inverted, then the child's links from the common frame down.
  std::vector<Step> chain = steps_up(from_parent, true);
  std::vector<Step> child_steps = steps_up(from_child, false);
  chain.insert(chain.end(), std::make_move_iterator(child_steps.rbegin()), std::make_move_iterator(child_steps.rend()));
  const Step* clock = nullptr;
  for (const Step& s : chain) {
    if (!s.fixed && (clock == nullptr || s.poses.size() > clock->poses.size())) clock = &s;
  }
  Trajectory trajectory;
  const std::vector<int64_t> stamps = clock ? clock->poses.stamps_ns : std::vector<int64_t>{0};
  for (const int64_t t : stamps) {
    SE3d parent_from_child;
    bool known = true;
    for (const Step& s : chain) {
      SE3d link;
      if (s.fixed) {
        link = s.poses.poses.back();
      } else if (!Interpolate(s.poses, t, &link)) {
        known = false;
        break;
      }
      parent_from_child = parent_from_child * (s.inverted ? link.Inverse() : link);
    }
    if (known) trajectory.Add(t, parent_from_child);
  }
  if (trajectory.empty()) {
    throw InputError(bag.path().string() + ": the transforms from " + parent + " to " + child +
                     " never overlap in time");
  }
  return trajectory;
}

}  // namespace dsm
