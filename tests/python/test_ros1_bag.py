# SPDX-License-Identifier: MIT
"""ROS 1 bags written by ROS's own writer (ros1_bags.py) read by dsm: `dsm info` lists what the
writer wrote, and a run on a bag of the synthetic loop's frames gives the trajectories of the run
on the same frames from a folder, byte for byte, whatever the chunk compression, image encoding or
the message that carries the ground truth. The real bags of ../shared/data/ros give the poses
python3-rosbag reads from them."""
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest
import rosbag

import ros1_bags as rb
from recordings import OUTPUTS, assert_same_outputs, gray_frames, read_tum, run_recording as run_bag

SHARED_ROS = pathlib.Path(os.environ.get("DSM_SHARED_DATA", pathlib.Path(__file__).parents[2] / ".." / "shared" / "data")) / "ros"


def image_messages(loop, encoding="mono8", topic="/cam0/image_raw", latency_ns=0):
    _, _, frames, stamps, _, _ = loop
    return [(topic, rb.image_message(f, encoding, t), t + latency_ns) for f, t in zip(frames, stamps)]


def ground_truth_messages(loop, kind, topic="/gt"):
    return [(topic, rb.pose_message(kind, t, p, q, child="cam0"), t) for t, p, q in loop[4]]


@pytest.mark.parametrize("compression,encoding", [("none", "mono8"), ("lz4", "rgb8"), ("bz2", "bgra8")])
def test_raw_images_run_as_the_folder(dsm_bin, loop, tmp_path, compression, encoding):
    bag = rb.write_bag(tmp_path / "loop.bag", image_messages(loop, encoding) + ground_truth_messages(loop, "PoseStamped"),
                       compression)
    scene, reference = loop[0], loop[1]
    run = run_bag(dsm_bin, bag, tmp_path / "run", "--calib", str(scene / "camera.yaml"), "--gt-topic", "/gt")
    assert_same_outputs(run, reference)


def test_info_lists_the_topics_as_written(dsm_bin, loop, tmp_path):
    scene = loop[0]
    bag = rb.write_bag(tmp_path / "loop.bag", image_messages(loop) + ground_truth_messages(loop, "Odometry", "/odom"),
                       "lz4")
    result = subprocess.run([dsm_bin, "info", str(bag), "--calib", str(scene / "camera.yaml")], capture_output=True,
                            text=True, check=True)
    lines = result.stdout.splitlines()
    with rosbag.Bag(str(bag)) as b:
        info = b.get_type_and_topic_info().topics
    for topic, entry in info.items():
        assert any(line.split() == [topic, entry.msg_type, str(entry.message_count)] for line in lines), result.stdout
    assert "frames:       120" in lines, result.stdout


def test_png_messages_and_camera_info_run_as_the_folder(dsm_bin, loop, tmp_path):
    scene, reference, _, stamps, _, pngs = loop
    messages = [("/cam0/image_raw/compressed", rb.compressed_message(p, t), t) for p, t in zip(pngs, stamps)]
    messages.append(("/cam0/camera_info", rb.camera_info(320, 240, 192, 192, 159.5, 119.5, t_ns=stamps[0]), stamps[0]))
    bag = rb.write_bag(tmp_path / "loop.bag", messages + ground_truth_messages(loop, "TransformStamped"))
    # The calibration from the bag's CameraInfo, which says nothing of the shutter: told global, as
    # camera.yaml says.
    run = run_bag(dsm_bin, bag, tmp_path / "run", "--gt-topic", "/gt", "--line-delay-us", "0")
    assert_same_outputs(run, reference)


def test_header_stamps_time_the_frames_of_a_bag_logged_late(dsm_bin, loop, tmp_path):
    """A bag recorded live logs each message after its capture: the frames take the header stamps."""
    scene, reference = loop[0], loop[1]
    messages = image_messages(loop, latency_ns=7_000_000) + ground_truth_messages(loop, "Odometry")
    bag = rb.write_bag(tmp_path / "late.bag", messages)
    run = run_bag(dsm_bin, bag, tmp_path / "run", "--calib", str(scene / "camera.yaml"), "--gt-topic", "/gt")
    assert_same_outputs(run, reference)


def test_tf_chain_gives_the_camera_poses(dsm_bin, loop, tmp_path):
    """world -> body on /tf, body -> cam0 fixed on /tf_static: the chain world -> cam0 is the ground truth."""
    scene, reference = loop[0], loop[1]
    # A fixed body_from_cam: 90 degrees about z and a lever arm; world_from_body = world_from_cam * cam_from_body.
    q_bc = np.array([0.0, 0.0, np.sqrt(0.5), np.sqrt(0.5)])  # x y z w
    t_bc = np.array([0.1, -0.05, 0.02])

    def rot(q):
        x, y, z, w = q
        return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])

    def quat(r):
        w = np.sqrt(max(0.0, 1 + r[0, 0] + r[1, 1] + r[2, 2])) / 2
        return np.array([(r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w), w])

    r_bc = rot(q_bc)
    messages = image_messages(loop)
    for t, p, q in loop[4]:
        r_wc = rot(q)
        r_wb = r_wc @ r_bc.T
        t_wb = np.array(p) - r_wb @ t_bc
        tf = rb.pose_message("TransformStamped", t, tuple(t_wb), tuple(quat(r_wb)), parent="world", child="body")
        messages.append(("/tf", rb.tf_message([tf]), t))
    static = rb.pose_message("TransformStamped", loop[3][0], tuple(t_bc), tuple(q_bc), parent="body", child="cam0")
    messages.append(("/tf_static", rb.tf_message([static]), loop[3][0]))
    bag = rb.write_bag(tmp_path / "tf.bag", messages, "lz4")
    run = run_bag(dsm_bin, bag, tmp_path / "run", "--calib", str(scene / "camera.yaml"), "--gt-frames", "world", "cam0")
    assert_same_outputs(run, reference, with_eval=False)
    ate = json.loads((run / "eval.json").read_text())["keyframes"]["ape"]["rmse"]
    reference_ate = json.loads((reference / "eval.json").read_text())["keyframes"]["ape"]["rmse"]
    assert ate == pytest.approx(reference_ate, rel=1e-6)


def test_bayer_and_colour_orders_read_alike(dsm_bin, loop, tmp_path):
    """rgb8 and bgr8 messages of the same colours give the same run; a Bayer mosaic of the grey
    frames, demosaiced, tracks the loop."""
    scene, reference, frames, stamps, _, _ = loop
    colour = np.stack([frames, 255 - frames, frames // 2], axis=3)  # R, G, B
    runs = {}
    for encoding, pixels in [("rgb8", colour), ("bgr8", colour[..., ::-1])]:
        messages = [("/cam", rb.image_message(f, encoding, t), t) for f, t in zip(pixels, stamps)]
        bag = rb.write_bag(tmp_path / f"{encoding}.bag", messages)
        runs[encoding] = run_bag(dsm_bin, bag, tmp_path / encoding, "--calib", str(scene / "camera.yaml"))
    for name in OUTPUTS:
        assert (runs["rgb8"] / name).read_bytes() == (runs["bgr8"] / name).read_bytes(), name
    messages = [("/cam", rb.image_message(f, "bayer_rggb8", t), t) for f, t in zip(frames, stamps)]
    messages += ground_truth_messages(loop, "PoseStamped")
    bag = rb.write_bag(tmp_path / "bayer.bag", messages)
    run = run_bag(dsm_bin, bag, tmp_path / "bayer", "--calib", str(scene / "camera.yaml"), "--gt-topic", "/gt")
    stats = json.loads((run / "stats.json").read_text())
    assert stats["frames_tracked"] == 120
    ate = json.loads((run / "eval.json").read_text())["keyframes"]["ape"]["rmse"]
    reference_ate = json.loads((reference / "eval.json").read_text())["keyframes"]["ape"]["rmse"]
    assert ate < 2.0 * reference_ate


def shared_poses(bag_path, topic):
    """(t_ns, position, quaternion xyzw) of each pose message on `topic`, read by python3-rosbag."""
    rows = []
    with rosbag.Bag(str(bag_path)) as bag:
        for _, m, _ in bag.read_messages(topics=[topic]):
            p, q = m.pose.position, m.pose.orientation
            rows.append((m.header.stamp.to_nsec(), (p.x, p.y, p.z), (q.x, q.y, q.z, q.w)))
    return sorted(rows, key=lambda r: r[0])


def assert_same_poses(dsm_tum, expected):
    got = read_tum(dsm_tum)
    assert len(got) == len(expected)
    for (t, p, q), (te, pe, qe) in [(got[0], expected[0]), (got[-1], expected[-1])]:
        assert t == te
        assert np.allclose(p, pe, atol=1e-9)
        sign = 1.0 if np.dot(q, qe) >= 0 else -1.0  # q and -q are one rotation
        assert np.allclose(sign * np.array(q), qe, atol=1e-9)


def test_shared_pose_bag_gives_the_poses_rosbag_reads(dsm_bin, tmp_path):
    bag = SHARED_ROS / "ROS_example.bag"
    for topic in ["groundtruth", "ORB-SLAM", "S-PTAM"]:
        out = tmp_path / f"{topic}.tum"
        subprocess.run([dsm_bin, "info", str(bag), "--gt-topic", topic, "--gt-out", str(out)], check=True,
                       capture_output=True)
        assert_same_poses(out, shared_poses(bag, topic))


def test_shared_tf_bag_gives_the_chain_rosbag_reads(dsm_bin, tmp_path):
    """tf_example.bag (lz4 chunks): odom -> base_footprint on /tf, base_footprint -> base_link fixed."""
    bag = SHARED_ROS / "tf_example.bag"
    out = tmp_path / "odom_base_footprint.tum"
    subprocess.run([dsm_bin, "info", str(bag), "--gt-frames", "odom", "base_footprint", "--gt-out", str(out)],
                   check=True, capture_output=True)
    expected = []
    with rosbag.Bag(str(bag)) as b:
        for _, m, _ in b.read_messages(topics=["/tf"]):
            for tf in m.transforms:
                t, r = tf.transform.translation, tf.transform.rotation
                expected.append((tf.header.stamp.to_nsec(), (t.x, t.y, t.z), (r.x, r.y, r.z, r.w)))
    assert_same_poses(out, sorted(expected, key=lambda r: r[0]))


def test_shared_euroc_bags_run_as_its_folder(dsm_bin, tmp_path):
    """The shared EuRoC recording as ROS 1 bags (lz4 and bz2 chunks): its frames as mono8 Images,
    the body's poses of its ground truth as PoseStamped; with its sensor.yaml (T_BS) the runs give
    the folder run's trajectories and evaluation byte for byte."""
    euroc = SHARED_ROS.parent / "euroc_mh01_shake"
    cam0 = euroc / "mav0" / "cam0"
    rows = [line.split(",") for line in (cam0 / "data.csv").read_text().splitlines() if not line.startswith("#")]
    stamps = [int(r[0]) for r in rows]
    frames = gray_frames([cam0 / "data" / r[1].strip() for r in rows], 752, 480)
    messages = [("/cam0/image_raw", rb.image_message(f, "mono8", t), t) for f, t in zip(frames, stamps)]
    gt_csv = euroc / "mav0" / "state_groundtruth_estimate0" / "data.csv"
    for line in gt_csv.read_text().splitlines():
        if line.startswith("#"):
            continue
        f = line.split(",")
        t = int(f[0])
        position, (w, x, y, z) = tuple(map(float, f[1:4])), tuple(map(float, f[4:8]))
        messages.append(("/vicon/pose", rb.pose_message("PoseStamped", t, position, (x, y, z, w)), t))
    reference = run_bag(dsm_bin, euroc, tmp_path / "folder")
    for compression in ["lz4", "bz2"]:
        bag = rb.write_bag(tmp_path / f"euroc_{compression}.bag", messages, compression)
        run = run_bag(dsm_bin, bag, tmp_path / compression, "--calib", str(cam0 / "sensor.yaml"), "--gt-topic",
                      "/vicon/pose")
        assert_same_outputs(run, reference)
        bag.unlink()


def test_python_reads_and_runs_a_bag(loop, tmp_path):
    """dsm.read_dataset and dsm.run take a bag as they take the folder of the same frames."""
    dsm = pytest.importorskip("dsm", reason="the Python module is not built (DSM_BUILD_PYTHON off)")
    scene, reference = loop[0], loop[1]
    bag = rb.write_bag(tmp_path / "loop.bag", image_messages(loop) + ground_truth_messages(loop, "PoseStamped"), "lz4")
    from_bag = dsm.read_dataset(str(bag), "/cam0/image_raw", calib=str(scene / "camera.yaml"), gt_topic="/gt")
    from_folder = dsm.read_dataset(str(reference.parent / "folder"))
    assert len(from_bag) == len(from_folder) == 120
    assert from_bag.format == "bag"
    for i in [0, 57, 119]:
        assert from_bag[i].t_ns == from_folder[i].t_ns
        assert np.array_equal(from_bag[i].image, from_folder[i].image)
    assert np.array_equal(from_bag.ground_truth, from_folder.ground_truth)
    stats = dsm.run(str(bag), out=str(tmp_path / "run"), calib=str(scene / "camera.yaml"), gt_topic="/gt")
    assert stats["eval"] == json.loads((reference / "eval.json").read_text())
    with pytest.raises(dsm.InputError, match="no topic /nope"):
        dsm.read_dataset(str(bag), "/nope", calib=str(scene / "camera.yaml"))


@pytest.mark.parametrize("model,d,expected", [
    ("plumb_bob", [0.1, -0.05, 0.001, 0.002, 0.01], ("radtan", [0.1, -0.05, 0.001, 0.002, 0.01])),
    ("rational_polynomial", [0.1, -0.05, 0.001, 0.002, 0.01, 0, 0, 0], ("radtan", [0.1, -0.05, 0.001, 0.002, 0.01])),
    ("equidistant", [0.05, -0.01, 0.002, -0.001], ("equidistant", [0.05, -0.01, 0.002, -0.001])),
    ("rational_polynomial", [0.1, -0.05, 0.001, 0.002, 0.01, 0.3, 0, 0], None),
])
def test_camera_info_gives_the_lens_it_names(dsm_bin, loop, tmp_path, model, d, expected):
    """A CameraInfo's distortion model as dsm's camera model; one that does not reduce is refused."""
    info = rb.camera_info(320, 240, 192, 191, 159.5, 119.5, d, model)
    bag = rb.write_bag(tmp_path / "lens.bag", image_messages(loop)[:5] + [("/cam0/camera_info", info, loop[3][0])])
    result = subprocess.run([dsm_bin, "info", str(bag), "--topic", "/cam0/image_raw"], capture_output=True, text=True)
    if expected is None:
        assert result.returncode == 2
        assert f"{bag} /cam0/camera_info message 0: distortion model 'rational_polynomial' with 8 coefficients" in \
            result.stderr
        return
    assert result.returncode == 0, result.stderr
    lines = dict(line.split(":", 1) for line in result.stdout.splitlines() if ":" in line and not line.startswith(" "))
    assert lines["camera model"].strip() == expected[0]
    assert lines["intrinsics"].split() == ["fx", "192", "fy", "191", "cx", "159.5", "cy", "119.5"]
    assert [float(v) for v in lines["distortion"].split()] == expected[1]


def test_jpeg_messages_track_the_loop(dsm_bin, loop, tmp_path):
    """CompressedImage messages in JPEG (ffmpeg's encoder, quality 2) track as the PNG frames do."""
    scene, reference, _, stamps, _, pngs = loop
    jpegs = tmp_path / "jpeg"
    jpegs.mkdir()
    subprocess.run(["ffmpeg", "-v", "error", "-i", str(scene / "images" / "%06d.png"), "-q:v", "2",
                    str(jpegs / "%06d.jpg")], check=True)
    messages = []
    for jpeg, t in zip(sorted(jpegs.glob("*.jpg")), stamps):
        m = rb.compressed_message(jpeg, t)
        m.format = "jpeg"
        messages.append(("/cam0/image_raw/compressed", m, t))
    bag = rb.write_bag(tmp_path / "jpeg.bag", messages + ground_truth_messages(loop, "PoseStamped"), "lz4")
    run = run_bag(dsm_bin, bag, tmp_path / "run", "--calib", str(scene / "camera.yaml"), "--gt-topic", "/gt")
    assert json.loads((run / "stats.json").read_text())["frames_tracked"] == len(pngs)
    ate = json.loads((run / "eval.json").read_text())["keyframes"]["ape"]["rmse"]
    reference_ate = json.loads((reference / "eval.json").read_text())["keyframes"]["ape"]["rmse"]
    assert ate < 1.5 * reference_ate, (ate, reference_ate)
