# SPDX-License-Identifier: MIT
"""ROS 1 bags written by ROS's own writer (Debian's python3-rosbag and the ROS message classes of
python3-sensor-msgs, -geometry-msgs, -nav-msgs, -tf2-msgs) from a dataset folder: the frames as
sensor_msgs/Image in any encoding or as CompressedImage, the camera as CameraInfo, and poses as
PoseStamped, TransformStamped, Odometry or /tf transforms."""
import pathlib

import numpy as np
import rosbag
import rospy
from geometry_msgs.msg import PoseStamped, TransformStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, CompressedImage, Image
from std_msgs.msg import Header
from tf2_msgs.msg import TFMessage



def stamp(t_ns):
    return rospy.Time(t_ns // 10**9, t_ns % 10**9)


def image_message(gray, encoding, t_ns, frame_id="cam0"):
    """`gray` in `encoding`: every colour channel the grey value unless gray is already (h, w, c)."""
    h, w = gray.shape[:2]
    channels = {"mono8": 1, "rgb8": 3, "bgr8": 3, "rgba8": 4, "bgra8": 4}.get(encoding, 1)
    if encoding.startswith("bayer_"):
        pixels = gray
    elif gray.ndim == 3:
        pixels = gray
    else:
        pixels = np.repeat(gray[:, :, None], channels, axis=2) if channels > 1 else gray
        if channels == 4:
            pixels = pixels.copy()
            pixels[:, :, 3] = 255
    m = Image()
    m.header = Header(stamp=stamp(t_ns), frame_id=frame_id)
    m.height, m.width, m.encoding, m.is_bigendian = h, w, encoding, 0
    m.step = w * (pixels.shape[2] if pixels.ndim == 3 else 1)
    m.data = np.ascontiguousarray(pixels).tobytes()
    return m


def compressed_message(png_path, t_ns, frame_id="cam0"):
    m = CompressedImage()
    m.header = Header(stamp=stamp(t_ns), frame_id=frame_id)
    m.format = "png"
    m.data = pathlib.Path(png_path).read_bytes()
    return m


def camera_info(width, height, fx, fy, cx, cy, distortion=(), model="plumb_bob", t_ns=0):
    m = CameraInfo()
    m.header = Header(stamp=stamp(t_ns), frame_id="cam0")
    m.width, m.height, m.distortion_model = width, height, model
    m.D = list(distortion) if distortion else [0.0] * 5
    m.K = [fx, 0, cx, 0, fy, cy, 0, 0, 1]
    m.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    m.P = [fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0]
    return m


def pose_message(kind, t_ns, position, quaternion_xyzw, parent="world", child="body"):
    """One pose as `kind`: PoseStamped, TransformStamped or Odometry."""
    header = Header(stamp=stamp(t_ns), frame_id=parent)
    if kind == "PoseStamped":
        m = PoseStamped(header=header)
        pose = m.pose
    elif kind == "Odometry":
        m = Odometry(header=header, child_frame_id=child)
        pose = m.pose.pose
    else:
        m = TransformStamped(header=header, child_frame_id=child)
        m.transform.translation.x, m.transform.translation.y, m.transform.translation.z = position
        r = m.transform.rotation
        r.x, r.y, r.z, r.w = quaternion_xyzw
        return m
    pose.position.x, pose.position.y, pose.position.z = position
    pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = quaternion_xyzw
    return m


def tf_message(transforms):
    return TFMessage(transforms=transforms)


def write_bag(path, messages, compression="none"):
    """`messages`: (topic, message, log time in ns) in any order; written in that order."""
    with rosbag.Bag(str(path), "w", compression=compression) as bag:
        for topic, message, t_ns in messages:
            bag.write(topic, message, t=stamp(t_ns))
    return path
