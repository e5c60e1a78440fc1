// SPDX-License-Identifier: MIT
#include "dsm/bag/ros2_schemas.h"

#include <map>
#include <set>
#include <sstream>
#include <vector>

namespace dsm {

namespace {

// Each type's fields and the types among them (ROS 2's .msg texts, comments left out).
struct Definition {
  const char* text;
  std::vector<std::string> uses;
};

const std::map<std::string, Definition>& Definitions() {
  static const std::map<std::string, Definition> definitions = {
      {"builtin_interfaces/Time", {"int32 sec\nuint32 nanosec", {}}},
      {"std_msgs/Header", {"builtin_interfaces/Time stamp\nstring frame_id", {"builtin_interfaces/Time"}}},
      {"geometry_msgs/Point", {"float64 x\nfloat64 y\nfloat64 z", {}}},
      {"geometry_msgs/Vector3", {"float64 x\nfloat64 y\nfloat64 z", {}}},
      {"geometry_msgs/Quaternion", {"float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1", {}}},
      {"geometry_msgs/Pose",
       {"geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation", {"geometry_msgs/Point", "geometry_msgs/Quaternion"}}},
      {"geometry_msgs/Transform",
       {"geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation", {"geometry_msgs/Vector3", "geometry_msgs/Quaternion"}}},
      {"geometry_msgs/PoseStamped", {"std_msgs/Header header\ngeometry_msgs/Pose pose", {"std_msgs/Header", "geometry_msgs/Pose"}}},
      {"geometry_msgs/TransformStamped",
       {"std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform",
        {"std_msgs/Header", "geometry_msgs/Transform"}}},
      {"tf2_msgs/TFMessage", {"geometry_msgs/TransformStamped[] transforms", {"geometry_msgs/TransformStamped"}}},
      {"nav_msgs/Path",
       {"std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses", {"std_msgs/Header", "geometry_msgs/PoseStamped"}}},
      {"sensor_msgs/Image",
       {"std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\n"
        "uint8[] data",
        {"std_msgs/Header"}}},
      {"sensor_msgs/RegionOfInterest",
       {"uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify", {}}},
      {"sensor_msgs/CameraInfo",
       {"std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\nfloat64[9] k\n"
        "float64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nsensor_msgs/RegionOfInterest roi",
        {"std_msgs/Header", "sensor_msgs/RegionOfInterest"}}},
      {"sensor_msgs/PointField",
       {"uint8 INT8    = 1\nuint8 UINT8   = 2\nuint8 INT16   = 3\nuint8 UINT16  = 4\nuint8 INT32   = 5\n"
        "uint8 UINT32  = 6\nuint8 FLOAT32 = 7\nuint8 FLOAT64 = 8\nstring name\nuint32 offset\nuint8 datatype\n"
        "uint32 count",
        {}}},
      {"sensor_msgs/PointCloud2",
       {"std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\nbool is_bigendian\n"
        "uint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense",
        {"std_msgs/Header", "sensor_msgs/PointField"}}},
  };
  return definitions;
}

void Dependencies(const std::string& type, std::vector<std::string>* order, std::set<std::string>* seen) {
  for (const std::string& used : Definitions().at(type).uses) {
    if (seen->insert(used).second) {
      order->push_back(used);
      Dependencies(used, order, seen);
    }
  }
}

}  // namespace

std::string Ros2Schema(const std::string& type) {
  const size_t msg = type.find("/msg/");
  const std::string name = msg == std::string::npos ? type : type.substr(0, msg) + type.substr(msg + 4);
  std::ostringstream text;
  text << Definitions().at(name).text;
  std::vector<std::string> order;
  std::set<std::string> seen;
  Dependencies(name, &order, &seen);
  for (const std::string& used : order) {
    text << "\n================================================================================\nMSG: " << used << "\n"
         << Definitions().at(used).text;
  }
  return text.str();
}

}  // namespace dsm
