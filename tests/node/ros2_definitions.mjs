// SPDX-License-Identifier: MIT
// The ROS 2 message definitions the tests write (as ROS 2 ships them, dependencies appended the
// way rosbag2 writes an MCAP schema), and a CDR writer for each, by @foxglove/rosmsg2-serialization.
import { parse } from "@foxglove/rosmsg";
import { MessageWriter } from "@foxglove/rosmsg2-serialization";

const SEPARATOR = "\n================================================================================\nMSG: ";

const MSG = {
  "builtin_interfaces/Time": "int32 sec\nuint32 nanosec",
  "std_msgs/Header": "builtin_interfaces/Time stamp\nstring frame_id",
  "geometry_msgs/Point": "float64 x\nfloat64 y\nfloat64 z",
  "geometry_msgs/Vector3": "float64 x\nfloat64 y\nfloat64 z",
  "geometry_msgs/Quaternion": "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1",
  "geometry_msgs/Pose": "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation",
  "geometry_msgs/Transform": "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation",
  "geometry_msgs/Twist": "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular",
  "geometry_msgs/PoseWithCovariance": "geometry_msgs/Pose pose\nfloat64[36] covariance",
  "geometry_msgs/TwistWithCovariance": "geometry_msgs/Twist twist\nfloat64[36] covariance",
  "geometry_msgs/PoseStamped": "std_msgs/Header header\ngeometry_msgs/Pose pose",
  "geometry_msgs/TransformStamped": "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform",
  "tf2_msgs/TFMessage": "geometry_msgs/TransformStamped[] transforms",
  "nav_msgs/Odometry":
    "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n" +
    "geometry_msgs/TwistWithCovariance twist",
  "sensor_msgs/Image":
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\nuint8[] data",
  "sensor_msgs/CompressedImage": "std_msgs/Header header\nstring format\nuint8[] data",
  "sensor_msgs/RegionOfInterest": "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify",
  "sensor_msgs/CameraInfo":
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\nfloat64[9] k\n" +
    "float64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nsensor_msgs/RegionOfInterest roi",
};

// "pkg/msg/Type" or "pkg/Type" -> "pkg/Type".
const short = (type) => type.replace("/msg/", "/");

function dependencies(type, seen = new Set()) {
  for (const line of MSG[type].split("\n")) {
    const field = line.split(" ")[0].replace(/\[\d*\]$/, "");
    if (field.includes("/") && !seen.has(field)) {
      seen.add(field);
      dependencies(field, seen);
    }
  }
  return seen;
}

// The schema text of `type` ("sensor_msgs/msg/Image"): its definition, then each dependency's.
export function schemaText(type) {
  const name = short(type);
  if (!MSG[name]) throw new Error(`no definition of ${type}`);
  return [MSG[name], ...[...dependencies(name)].map((d) => `${d}\n${MSG[d]}`)].join(SEPARATOR);
}

const writers = new Map();
// The CDR bytes (encapsulation header included) of `message` of `type`.
export function serialize(type, message) {
  if (!writers.has(type)) writers.set(type, new MessageWriter(parse(schemaText(type), { ros2: true })));
  return writers.get(type).writeMessage(message);
}
