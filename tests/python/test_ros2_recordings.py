# SPDX-License-Identifier: MIT
"""ROS 2 recordings written by the MCAP and Foxglove projects' own writers (ros2_recordings.py) read
by dsm: MCAP files (chunks uncompressed, lz4, zstd) and rosbag2 SQLite bags of the synthetic loop's
frames run as the folder of the same frames, byte for byte; the shared nav2_turtlebot.mcap and
tf_example/ give the poses @mcap/core and the Foxglove CDR reader read from them."""
import json
import os
import pathlib
import sqlite3
import subprocess

import numpy as np
import pytest

import ros2_recordings as r2
from recordings import assert_same_outputs, gray_frames, run_recording

SHARED = pathlib.Path(os.environ.get("DSM_SHARED_DATA", pathlib.Path(__file__).parents[2] / ".." / "shared" / "data"))


def loop_recording(loop, encoding="mono8", gt="PoseStamped", camera_info=False, topic="/cam0/image_raw"):
    _, _, frames, stamps, poses, _ = loop
    recording = r2.Recording()
    if camera_info:
        recording.add("/cam0/camera_info", "sensor_msgs/msg/CameraInfo", stamps[0],
                      r2.camera_info(stamps[0], 320, 240, 192, 192, 159.5, 119.5))
    channels = {"rgb8": 3, "bgra8": 4}.get(encoding, 1)
    for frame, (t, p, q), t_frame in zip(frames, poses, stamps):
        pixels = frame if channels == 1 else np.repeat(frame[:, :, None], channels, axis=2)
        if channels == 4:
            pixels[:, :, 3] = 255
        recording.add(topic, "sensor_msgs/msg/Image", t_frame, r2.image(t_frame, 240, 320, encoding), pixels)
        if gt:
            type_, fields = r2.pose(gt, t, p, q, child="cam0")
            recording.add("/gt", type_, t, fields)
    return recording


@pytest.mark.parametrize("compression,encoding,gt", [("none", "mono8", "PoseStamped"), ("lz4", "rgb8", "Odometry"),
                                                     ("zstd", "bgra8", "TransformStamped")])
def test_mcap_runs_as_the_folder(dsm_bin, loop, tmp_path, compression, encoding, gt):
    scene, reference = loop[0], loop[1]
    mcap = loop_recording(loop, encoding, gt).write_mcap(tmp_path / "loop.mcap", compression, chunk_size=300_000)
    run = run_recording(dsm_bin, mcap, tmp_path / "run", "--calib", str(scene / "camera.yaml"), "--gt-topic", "/gt")
    assert_same_outputs(run, reference)


def test_sqlite_bag_with_camera_info_runs_as_the_folder(dsm_bin, loop, tmp_path):
    reference = loop[1]
    bag = loop_recording(loop, gt="Odometry", camera_info=True).write_sqlite_bag(tmp_path / "loop_bag")
    # The calibration from the bag's CameraInfo, which says nothing of the shutter: told global, as
    # the scene's camera.yaml says.
    run = run_recording(dsm_bin, bag, tmp_path / "run", "--gt-topic", "/gt", "--line-delay-us", "0")
    assert_same_outputs(run, reference)
    # The .db3 file alone reads as the folder.
    run = run_recording(dsm_bin, bag / "bag_0.db3", tmp_path / "run_db3", "--gt-topic", "/gt", "--line-delay-us", "0")
    assert_same_outputs(run, reference)


def test_info_lists_what_the_writers_wrote(dsm_bin, loop, tmp_path):
    scene = loop[0]
    mcap = loop_recording(loop, gt="Odometry", camera_info=True).write_mcap(tmp_path / "loop.mcap", "zstd")
    summary = json.loads(subprocess.run(["node", str(r2.node_tools() / "read_ros2.mjs"), "summary", str(mcap)],
                                        capture_output=True, text=True, check=True).stdout)
    lines = subprocess.run([dsm_bin, "info", str(mcap), "--calib", str(scene / "camera.yaml")], capture_output=True,
                           text=True, check=True).stdout.splitlines()
    for channel in summary["channels"]:
        expected = [channel["topic"], channel["schemaName"].replace("/msg/", "/"), str(channel["count"])]
        assert any(line.split() == expected for line in lines), (expected, lines)
    assert "frames:       120" in lines


def node_poses(*args):
    rows = subprocess.run(["node", str(r2.node_tools() / "read_ros2.mjs"), *args], capture_output=True, text=True,
                          check=True).stdout
    return sorted(((int(r[0]), tuple(r[1]), tuple(r[2])) + tuple(r[3:]) for r in json.loads(rows)), key=lambda r: r[0])


def assert_same_poses(dsm_tum, expected):
    from recordings import read_tum
    got = read_tum(dsm_tum)
    assert len(got) == len(expected)
    for (t, p, q), (te, pe, qe, *_) in [(got[0], expected[0]), (got[-1], expected[-1])]:
        assert t == te
        assert np.allclose(p, pe, atol=1e-9)
        sign = 1.0 if np.dot(q, qe) >= 0 else -1.0  # q and -q are one rotation
        assert np.allclose(sign * np.array(q), qe, atol=1e-9)


@pytest.mark.parametrize("topic", ["/odom", "/amcl_pose"])
def test_shared_mcap_gives_the_poses_mcap_core_reads(dsm_bin, tmp_path, topic):
    mcap = SHARED / "ros" / "nav2_turtlebot.mcap"
    out = tmp_path / "poses.tum"
    subprocess.run([dsm_bin, "info", str(mcap), "--gt-topic", topic, "--gt-out", str(out)], check=True,
                   capture_output=True)
    assert_same_poses(out, node_poses("poses", str(mcap), topic))


def test_shared_mcap_tf_chain(dsm_bin, tmp_path):
    """odom -> base_link is one moving link of /tf: the chain is its transforms."""
    mcap = SHARED / "ros" / "nav2_turtlebot.mcap"
    out = tmp_path / "chain.tum"
    subprocess.run([dsm_bin, "info", str(mcap), "--gt-frames", "odom", "base_link", "--gt-out", str(out)],
                   check=True, capture_output=True)
    links = [r for r in node_poses("poses", str(mcap), "/tf") if r[3] == "base_link"]
    assert_same_poses(out, links)


def test_shared_sqlite_bag_gives_the_poses_the_cdr_reader_reads(dsm_bin, tmp_path):
    """tf_example/ (written by the rosbags library): its /tf rows as SQLite holds them, decoded by
    @foxglove/rosmsg2-serialization, against the chain odom -> base_footprint dsm reads."""
    bag = SHARED / "ros" / "tf_example"
    db = sqlite3.connect(f"file:{bag / 'tf_example.db3'}?immutable=1", uri=True)
    blobs = tmp_path / "tf.bin"
    with open(blobs, "wb") as out_file:
        for (data,) in db.execute("SELECT m.data FROM messages m JOIN topics t ON m.topic_id = t.id "
                                  "WHERE t.name = '/tf' ORDER BY m.timestamp"):
            out_file.write(len(data).to_bytes(4, "little") + data)
    out = tmp_path / "chain.tum"
    subprocess.run([dsm_bin, "info", str(bag), "--gt-frames", "odom", "base_footprint", "--gt-out", str(out)],
                   check=True, capture_output=True)
    assert_same_poses(out, node_poses("cdr-poses", "tf2_msgs/msg/TFMessage", str(blobs)))


@pytest.mark.parametrize("container", ["mcap", "sqlite"])
def test_shared_euroc_as_ros2_runs_as_its_folder(dsm_bin, tmp_path, container):
    """The shared EuRoC recording as an MCAP file (zstd chunks) and a rosbag2 SQLite bag: its frames
    as mono8 Images, the body's poses of its ground truth as PoseStamped; with its sensor.yaml the
    runs give the folder run's trajectories and evaluation byte for byte."""
    euroc = SHARED / "euroc_mh01_shake"
    cam0 = euroc / "mav0" / "cam0"
    rows = [line.split(",") for line in (cam0 / "data.csv").read_text().splitlines() if not line.startswith("#")]
    frames = gray_frames([cam0 / "data" / r[1].strip() for r in rows], 752, 480)
    recording = r2.Recording()
    for frame, row in zip(frames, rows):
        t = int(row[0])
        recording.add("/cam0/image_raw", "sensor_msgs/msg/Image", t, r2.image(t, 480, 752), frame)
    for line in (euroc / "mav0" / "state_groundtruth_estimate0" / "data.csv").read_text().splitlines():
        if line.startswith("#"):
            continue
        f = line.split(",")
        w, x, y, z = map(float, f[4:8])
        type_, fields = r2.pose("PoseStamped", int(f[0]), tuple(map(float, f[1:4])), (x, y, z, w))
        recording.add("/vicon/pose", type_, int(f[0]), fields)
    recording.messages.sort(key=lambda m: m[2])
    if container == "mcap":
        recorded = recording.write_mcap(tmp_path / "euroc.mcap", "zstd", chunk_size=4 << 20)
    else:
        recorded = recording.write_sqlite_bag(tmp_path / "euroc_bag")
    reference = run_recording(dsm_bin, euroc, tmp_path / "folder")
    run = run_recording(dsm_bin, recorded, tmp_path / container, "--calib", str(cam0 / "sensor.yaml"), "--gt-topic",
                        "/vicon/pose")
    assert_same_outputs(run, reference)


def test_mcap_output_reads_back_with_mcap_core(dsm_bin, loop, tmp_path):
    """`dsm run --mcap`: @mcap/core reads every channel, schema and message count as stats.json says
    they were written, and the Foxglove CDR reader decodes each message from the file's schemas to
    what the run's other outputs hold."""
    from recordings import read_tum
    scene = loop[0]
    out, mcap = tmp_path / "run", tmp_path / "run.mcap"
    run_recording(dsm_bin, scene, out, "--mcap", str(mcap))
    written = json.loads((out / "stats.json").read_text())["mcap"]
    assert written["file"] == str(mcap)
    tools = str(r2.node_tools() / "read_ros2.mjs")
    summary = json.loads(subprocess.run(["node", tools, "summary", str(mcap)], capture_output=True, text=True,
                                        check=True).stdout)
    types = {"/dsm/camera_pose": "geometry_msgs/msg/PoseStamped", "/tf": "tf2_msgs/msg/TFMessage",
             "/dsm/keyframe_pose": "geometry_msgs/msg/PoseStamped", "/dsm/keyframe_image": "sensor_msgs/msg/Image",
             "/dsm/camera_info": "sensor_msgs/msg/CameraInfo", "/dsm/map": "sensor_msgs/msg/PointCloud2",
             "/dsm/trajectory": "nav_msgs/msg/Path"}
    assert {c["topic"]: (c["schemaName"], c["schemaEncoding"], c["messageEncoding"], c["count"])
            for c in summary["channels"]} == {
        topic: (types[topic], "ros2msg", "cdr", count) for topic, count in written["messages"].items()}
    assert summary["messageCount"] == sum(written["messages"].values())

    frames, keyframes = read_tum(out / "frames.tum"), read_tum(out / "keyframes.tum")
    assert written["messages"]["/dsm/camera_pose"] == written["messages"]["/tf"] == len(frames)
    assert written["messages"]["/dsm/keyframe_pose"] == written["messages"]["/dsm/keyframe_image"] == len(keyframes)
    decoded = json.loads(subprocess.run(["node", tools, "decode", str(mcap)], capture_output=True, text=True,
                                        check=True).stdout)
    assert {topic: d["count"] for topic, d in decoded.items()} == written["messages"]

    def row(pose_stamped):
        stamp, pose = pose_stamped["header"]["stamp"], pose_stamped["pose"]
        p, q = pose["position"], pose["orientation"]
        return stamp["sec"] * 10**9 + stamp["nanosec"], [p["x"], p["y"], p["z"]], [q["x"], q["y"], q["z"], q["w"]]

    for message, (t, p, q) in [(decoded["/dsm/camera_pose"]["last"], frames[-1]),
                               (decoded["/dsm/keyframe_pose"]["last"], keyframes[-1])]:
        t_got, p_got, q_got = row(message)
        assert t_got == t and np.allclose(p_got, p, atol=1e-8) and np.allclose(q_got, q, atol=1e-8)
    tf = decoded["/tf"]["last"]["transforms"][0]
    assert (tf["header"]["frame_id"], tf["child_frame_id"]) == ("map", "camera")
    path = decoded["/dsm/trajectory"]["first"]
    assert len(path["poses"]) == len(keyframes)
    assert np.allclose(row(path["poses"][-1])[1], keyframes[-1][1], atol=1e-8)
    image = decoded["/dsm/keyframe_image"]["first"]
    assert (image["encoding"], image["height"], image["width"], image["step"], image["data"]) == (
        "mono8", 240, 320, 320, 240 * 320)
    cloud = decoded["/dsm/map"]["first"]
    vertices = next(int(line.split()[2]) for line in (out / "map.ply").read_bytes().split(b"end_header")[0]
                    .decode().splitlines() if line.startswith("element vertex"))
    assert (cloud["height"], cloud["width"], cloud["point_step"], cloud["data"]) == (1, vertices, 16, 16 * vertices)
    assert [f["name"] for f in cloud["fields"]] == ["x", "y", "z", "intensity"]
    # dsm reads its own file back: its keyframe images with their camera are a recording.
    lines = subprocess.run([dsm_bin, "info", str(mcap)], capture_output=True, text=True, check=True).stdout
    assert f"frames:       {len(keyframes)}" in lines
