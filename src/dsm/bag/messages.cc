// SPDX-License-Identifier: MIT
#include "dsm/bag/messages.h"

#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

// geometry_msgs/Point or Vector3.
Eigen::Vector3d ReadVector3(WireReader& in) {
  Eigen::Vector3d v;
  in.F64Array(v.data(), 3);
  return v;
}

// geometry_msgs/Quaternion (x, y, z, w).
Eigen::Quaterniond ReadQuaternion(WireReader& in, const std::string& where) {
  double xyzw[4];
  in.F64Array(xyzw, 4);
  const Eigen::Quaterniond q(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
  CheckQuaternion(q, where);
  return q;
}

// geometry_msgs/Pose: a point and then a quaternion; geometry_msgs/Transform: a vector and then a
// quaternion.
SE3d ReadPose(WireReader& in, const std::string& where) {
  const Eigen::Vector3d t = ReadVector3(in);
  if (!t.allFinite()) throw InputError(where + ": a pose whose position is not finite");
  return SE3d(ReadQuaternion(in, where), t);
}

StampedPose ReadTransformStamped(WireReader& in, const std::string& where) {
  StampedPose p;
  p.parent = in.Header(&p.stamp_ns);
  p.child = in.String();
  p.pose = ReadPose(in, where);
  return p;
}

}  // namespace

ImageMessage DecodeImage(WireReader& in) {
  ImageMessage m;
  m.frame_id = in.Header(&m.stamp_ns);
  m.height = in.U32();
  m.width = in.U32();
  m.encoding = in.String();
  m.big_endian = in.U8() != 0;
  m.step = in.U32();
  m.data = in.ByteSequence(&m.size);
  return m;
}

CompressedImageMessage DecodeCompressedImage(WireReader& in) {
  CompressedImageMessage m;
  m.frame_id = in.Header(&m.stamp_ns);
  m.format = in.String();
  m.data = in.ByteSequence(&m.size);
  return m;
}

CameraInfoMessage DecodeCameraInfo(WireReader& in) {
  CameraInfoMessage m;
  m.frame_id = in.Header(&m.stamp_ns);
  m.height = in.U32();
  m.width = in.U32();
  m.distortion_model = in.String();
  m.d = in.F64Sequence();
  in.F64Array(m.k.data(), 9);
  double unused[12];
  in.F64Array(unused, 9);   // R
  in.F64Array(unused, 12);  // P
  m.binning_x = in.U32();
  m.binning_y = in.U32();
  m.roi_x = in.U32();
  m.roi_y = in.U32();
  m.roi_height = in.U32();
  m.roi_width = in.U32();
  in.U8();  // roi.do_rectify
  return m;
}

bool IsPoseType(const std::string& type) {
  return type == "geometry_msgs/PoseStamped" || type == "geometry_msgs/PoseWithCovarianceStamped" ||
         type == "geometry_msgs/TransformStamped" || type == "nav_msgs/Odometry" || type == "tf2_msgs/TFMessage";
}

std::vector<StampedPose> DecodePoses(const std::string& type, WireReader& in) {
  const std::string where = "a " + type + " message";
  if (type == "geometry_msgs/PoseStamped" || type == "geometry_msgs/PoseWithCovarianceStamped") {
    StampedPose p;
    p.parent = in.Header(&p.stamp_ns);
    p.pose = ReadPose(in, where);
    return {p};
  }
  if (type == "geometry_msgs/TransformStamped") return {ReadTransformStamped(in, where)};
  if (type == "nav_msgs/Odometry") {
    StampedPose p;
    p.parent = in.Header(&p.stamp_ns);
    p.child = in.String();
    p.pose = ReadPose(in, where);
    return {p};
  }
  if (type == "tf2_msgs/TFMessage") {
    // A TransformStamped takes at least 8 + 4 + 4 + 7 * 8 bytes (ROS 1 adds a seq).
    std::vector<StampedPose> poses(in.SequenceCount(72));
    for (StampedPose& p : poses) p = ReadTransformStamped(in, where);
    return poses;
  }
  throw InputError("messages of type " + type + " carry no pose dsm reads (PoseStamped, PoseWithCovarianceStamped, "
                   "TransformStamped, Odometry, TFMessage)");
}

}  // namespace dsm
