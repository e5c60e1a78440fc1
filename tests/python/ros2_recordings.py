# SPDX-License-Identifier: MIT
"""ROS 2 recordings written by the MCAP and Foxglove projects' own writers (tests/node/write_ros2.mjs:
@mcap/core, @foxglove/rosmsg2-serialization) from messages described here as plain dicts: an MCAP
file, or a rosbag2 SQLite bag (the CDR messages put into rosbag2's tables by Python's sqlite3, with
the metadata.yaml rosbag2 writes)."""
import json
import os
import pathlib
import sqlite3
import subprocess
import tempfile

import numpy as np


def node_tools():
    """The folder with write_ros2.mjs and its node_modules (ctest sets DSM_NODE_TOOLS)."""
    folder = pathlib.Path(os.environ.get("DSM_NODE_TOOLS", ""))
    assert (folder / "write_ros2.mjs").is_file() and (folder / "node_modules").is_dir(), \
        "DSM_NODE_TOOLS must name the build's tests/node folder (ctest sets it)"
    return folder


def header(t_ns, frame_id):
    return {"stamp": {"sec": t_ns // 10**9, "nanosec": t_ns % 10**9}, "frame_id": frame_id}


def image(t_ns, height, width, encoding="mono8", frame_id="cam0"):
    """A sensor_msgs/msg/Image without its data (the writer takes it from the raw file)."""
    channels = {"rgb8": 3, "bgr8": 3, "rgba8": 4, "bgra8": 4}.get(encoding, 1)
    return {"header": header(t_ns, frame_id), "height": height, "width": width, "encoding": encoding,
            "is_bigendian": 0, "step": width * channels}


def camera_info(t_ns, width, height, fx, fy, cx, cy, d=(0.0,) * 5, model="plumb_bob"):
    return {"header": header(t_ns, "cam0"), "height": height, "width": width, "distortion_model": model,
            "d": list(d), "k": [fx, 0, cx, 0, fy, cy, 0, 0, 1], "r": [1, 0, 0, 0, 1, 0, 0, 0, 1],
            "p": [fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0], "binning_x": 0, "binning_y": 0,
            "roi": {"x_offset": 0, "y_offset": 0, "height": 0, "width": 0, "do_rectify": False}}


def pose(kind, t_ns, position, quaternion_xyzw, parent="world", child="body"):
    """geometry_msgs/msg/PoseStamped, TransformStamped or nav_msgs/msg/Odometry: (type, fields)."""
    p = dict(zip("xyz", position))
    q = dict(zip("xyzw", quaternion_xyzw))
    if kind == "PoseStamped":
        return "geometry_msgs/msg/PoseStamped", {"header": header(t_ns, parent), "pose": {"position": p, "orientation": q}}
    if kind == "TransformStamped":
        return "geometry_msgs/msg/TransformStamped", {"header": header(t_ns, parent), "child_frame_id": child,
                                                      "transform": {"translation": p, "rotation": q}}
    zero = {"x": 0.0, "y": 0.0, "z": 0.0}
    return "nav_msgs/msg/Odometry", {
        "header": header(t_ns, parent), "child_frame_id": child,
        "pose": {"pose": {"position": p, "orientation": q}, "covariance": [0.0] * 36},
        "twist": {"twist": {"linear": zero, "angular": zero}, "covariance": [0.0] * 36}}


class Recording:
    """Messages in log-time order: (topic, type, log time ns, fields, image pixels or None)."""

    def __init__(self):
        self.messages = []

    def add(self, topic, type_, t_ns, fields, pixels=None):
        self.messages.append((topic, type_, t_ns, fields, pixels))

    def _manifest(self, folder, fmt, compression, chunk_size, chunked=True):
        raw = folder / "frames.raw"
        entries, offset = [], 0
        with open(raw, "wb") as out:
            for topic, type_, t_ns, fields, pixels in self.messages:
                entry = {"topic": topic, "type": type_, "log_time": str(t_ns), "message": fields}
                if pixels is not None:
                    data = np.ascontiguousarray(pixels).tobytes()
                    out.write(data)
                    entry["data"] = [offset, len(data)]
                    offset += len(data)
                entries.append(entry)
        manifest = folder / "manifest.json"
        manifest.write_text(json.dumps({"format": fmt, "compression": compression, "chunk_size": chunk_size,
                                        "chunked": chunked, "raw": str(raw), "messages": entries}))
        return manifest

    def _node(self, fmt, out, compression="none", chunk_size=1 << 20, chunked=True):
        with tempfile.TemporaryDirectory() as tmp:
            manifest = self._manifest(pathlib.Path(tmp), fmt, compression, chunk_size, chunked)
            subprocess.run(["node", str(node_tools() / "write_ros2.mjs"), str(manifest), str(out)], check=True)

    def write_mcap(self, path, compression="none", chunk_size=1 << 20, chunked=True):
        """An MCAP file; chunked (and indexed) unless `chunked` is False."""
        self._node("mcap", path, compression, chunk_size, chunked)
        return path

    def write_sqlite_bag(self, folder):
        """A rosbag2 bag folder: metadata.yaml and one .db3 of rosbag2's schema."""
        folder.mkdir(parents=True, exist_ok=True)
        blobs = folder / "cdr.bin"
        self._node("cdr", blobs)
        data = blobs.read_bytes()
        blobs.unlink()
        db = sqlite3.connect(folder / "bag_0.db3")
        db.executescript("""
            CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
                                serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);
            CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL,
                                  data BLOB NOT NULL);
            CREATE INDEX timestamp_idx ON messages (timestamp ASC);""")
        topics, at = {}, 0
        counts = {}
        for topic, type_, t_ns, _, _ in self.messages:
            if topic not in topics:
                topics[topic] = len(topics) + 1
                db.execute("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", (topics[topic], topic, type_))
            length = int.from_bytes(data[at:at + 4], "little")
            db.execute("INSERT INTO messages(topic_id, timestamp, data) VALUES (?, ?, ?)",
                       (topics[topic], t_ns, data[at + 4:at + 4 + length]))
            at += 4 + length
            counts[topic] = counts.get(topic, 0) + 1
        db.commit()
        db.close()
        types = {topic: type_ for topic, type_, _, _, _ in self.messages}
        lines = ["rosbag2_bagfile_information:", "  version: 5", "  storage_identifier: sqlite3",
                 "  relative_file_paths:", "    - bag_0.db3", f"  message_count: {len(self.messages)}",
                 "  topics_with_message_count:"]
        for topic in topics:
            lines += ["    - topic_metadata:", f"        name: {topic}", f"        type: {types[topic]}",
                      "        serialization_format: cdr", "        offered_qos_profiles: ''",
                      f"      message_count: {counts[topic]}"]
        lines += ["  compression_format: ''", "  compression_mode: ''"]
        (folder / "metadata.yaml").write_text("\n".join(lines) + "\n")
        return folder
