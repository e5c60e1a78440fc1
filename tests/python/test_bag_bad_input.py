# SPDX-License-Identifier: MIT
"""Bad recordings and bad options for them: each a clear message naming the file (and the topic
where one is involved) and exit 2; a chunk damaged mid-way stops the run with its outputs written."""
import json
import struct
import subprocess

import numpy as np
import pytest

import ros1_bags as rb
from recordings import gray_frames

T0 = 1_600_000_000_000_000_000


@pytest.fixture(scope="module")
def scene(synthetic_run):
    return synthetic_run[0].parent / "scene"


@pytest.fixture(scope="module")
def frames(scene):
    return gray_frames(sorted((scene / "images").glob("*.png")), 320, 240)


def messages(frames, encoding="mono8", topic="/cam0/image_raw"):
    return [(topic, rb.image_message(f, encoding, T0 + i * 50_000_000), T0 + i * 50_000_000)
            for i, f in enumerate(frames)]


def run(dsm_bin, bag, scene, tmp_path, *args):
    return subprocess.run([dsm_bin, "run", str(bag), "--calib", str(scene / "camera.yaml"), "--out",
                           str(tmp_path / "run"), "--sequential", "--quiet", *args], capture_output=True, text=True)


def error_of(result):
    assert result.returncode == 2, result.stdout + result.stderr
    lines = result.stderr.strip().splitlines()
    assert lines and lines[-1].startswith("dsm: error: "), result.stderr
    return lines[-1][len("dsm: error: "):]


def test_truncated_bag(dsm_bin, scene, frames, tmp_path):
    bag = rb.write_bag(tmp_path / "whole.bag", messages(frames[:20]))
    cut = tmp_path / "cut.bag"
    cut.write_bytes(bag.read_bytes()[: bag.stat().st_size // 2])
    message = error_of(run(dsm_bin, cut, scene, tmp_path))
    assert message.startswith(f"{cut}: a ROS 1 bag whose index cannot be read: truncated"), message


def test_not_a_bag(dsm_bin, scene, tmp_path):
    junk = tmp_path / "junk.bag"
    junk.write_text("these are not the bytes of a bag\n")
    assert error_of(run(dsm_bin, junk, scene, tmp_path)).startswith(f"{junk}: not a ROS 1 bag")


def test_chunk_that_does_not_decompress_stops_the_run_with_its_outputs(dsm_bin, scene, frames, tmp_path):
    bag = rb.write_bag(tmp_path / "lz4.bag", messages(frames), "lz4")
    data = bytearray(bag.read_bytes())
    middle = len(data) * 6 // 10
    data[middle:middle + 4000] = bytes(4000)
    damaged = tmp_path / "damaged.bag"
    damaged.write_bytes(bytes(data))
    message = error_of(run(dsm_bin, damaged, scene, tmp_path))
    assert message.startswith(f"{damaged} topic /cam0/image_raw message "), message
    assert "the run stopped at frame" in message and "its outputs up to there are written" in message
    stats = json.loads((tmp_path / "run" / "stats.json").read_text())
    assert stats["damaged_input"] in message
    assert 0 < len((tmp_path / "run" / "frames.tum").read_text().splitlines()) < 120


def rewrite_header_field(bag, name, value_bytes):
    """The bag header record's field `name` (e.g. b"index_pos") given other bytes of the same length."""
    data = bytearray(bag.read_bytes())
    at = data.index(name + b"=", 0, 4096) + len(name) + 1
    data[at:at + len(value_bytes)] = value_bytes
    return bytes(data)


@pytest.mark.parametrize("field", ["index_pos", "chunk_count"])
def test_index_that_lies(dsm_bin, scene, frames, tmp_path, field):
    bag = rb.write_bag(tmp_path / "ok.bag", messages(frames[:30]), "lz4")
    lie = (struct.pack("<Q", bag.stat().st_size // 3) if field == "index_pos" else struct.pack("<I", 1000))
    lying = tmp_path / "lying.bag"
    lying.write_bytes(rewrite_header_field(bag, field.encode(), lie))
    assert error_of(run(dsm_bin, lying, scene, tmp_path)).startswith(f"{lying}: "), field


def test_unknown_encoding(dsm_bin, scene, frames, tmp_path):
    bag = rb.write_bag(tmp_path / "yuv.bag", messages(frames[:5], "yuv422"))
    message = error_of(run(dsm_bin, bag, scene, tmp_path))
    assert message.startswith(f"{bag} /cam0/image_raw message 0: image encoding 'yuv422' is not one dsm reads"), message


def test_missing_topics(dsm_bin, scene, frames, tmp_path):
    bag = rb.write_bag(tmp_path / "one.bag", messages(frames[:5]))
    assert error_of(run(dsm_bin, bag, scene, tmp_path, "--topic", "/cam1/image_raw")) == (
        f"{bag}: no topic /cam1/image_raw (the recording has /cam0/image_raw)")
    assert error_of(run(dsm_bin, bag, scene, tmp_path, "--gt-topic", "/vicon")) == (
        f"{bag}: no topic /vicon (the recording has /cam0/image_raw)")
    assert error_of(run(dsm_bin, bag, scene, tmp_path, "--gt-topic", "/cam0/image_raw")).startswith(
        f"{bag}: topic /cam0/image_raw is sensor_msgs/Image, not a pose")
    assert error_of(run(dsm_bin, bag, scene, tmp_path, "--gt-frames", "world", "cam0")).startswith(
        f"{bag}: no topic /tf")


def test_two_image_topics_need_a_choice(dsm_bin, scene, frames, tmp_path):
    bag = rb.write_bag(tmp_path / "two.bag", messages(frames[:5]) + messages(frames[:5], topic="/cam1/image_raw"))
    assert error_of(run(dsm_bin, bag, scene, tmp_path)) == (
        f"{bag}: 2 image topics (/cam0/image_raw, /cam1/image_raw): choose one with --topic")


def test_frames_of_another_size_than_the_calibration(dsm_bin, scene, frames, tmp_path):
    small = [f[:120, :160] for f in frames[:5]]
    bag = rb.write_bag(tmp_path / "small.bag", messages(small))
    message = error_of(run(dsm_bin, bag, scene, tmp_path))
    assert message == (f"{bag} /cam0/image_raw: images are 160x120 but the calibration {scene / 'camera.yaml'} "
                       "says 320x240"), message


def test_no_calibration(dsm_bin, frames, tmp_path):
    bag = rb.write_bag(tmp_path / "nocal.bag", messages(frames[:5]))
    result = subprocess.run([dsm_bin, "run", str(bag), "--out", str(tmp_path / "run")], capture_output=True, text=True)
    assert error_of(result) == (f"{bag}: no calibration for /cam0/image_raw: give one with --calib (the recording "
                                "has no sensor_msgs/CameraInfo)")


def test_unlinked_tf_frames(dsm_bin, scene, frames, tmp_path):
    tf = rb.tf_message([rb.pose_message("TransformStamped", T0, (0, 0, 0), (0, 0, 0, 1), parent="odom", child="base")])
    bag = rb.write_bag(tmp_path / "tf.bag", messages(frames[:5]) + [("/tf", tf, T0)])
    assert error_of(run(dsm_bin, bag, scene, tmp_path, "--gt-frames", "map", "cam0")) == (
        f"{bag}: no chain of transforms joins map and cam0 on /tf and /tf_static (links: odom -> base)")


# ROS 2 recordings (MCAP files, rosbag2 SQLite bags), written by the MCAP and Foxglove writers.

def ros2_recording(frames, n=40):
    import ros2_recordings as r2
    recording = r2.Recording()
    for i, f in enumerate(frames[:n]):
        t = T0 + i * 50_000_000
        recording.add("/cam0/image_raw", "sensor_msgs/msg/Image", t, r2.image(t, 240, 320), f)
    return recording


def test_truncated_mcap(dsm_bin, scene, frames, tmp_path):
    mcap = ros2_recording(frames).write_mcap(tmp_path / "whole.mcap", "zstd", chunk_size=200_000)
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(mcap.read_bytes()[: mcap.stat().st_size // 2])
    message = error_of(run(dsm_bin, cut, scene, tmp_path))
    assert message.startswith(f"{cut}: the record at ") and "runs past the end of the file" in message, message


def test_mcap_chunk_that_fails_its_crc_stops_the_run_with_its_outputs(dsm_bin, scene, frames, tmp_path):
    mcap = ros2_recording(frames, 120).write_mcap(tmp_path / "ok.mcap", "none", chunk_size=400_000)
    data = bytearray(mcap.read_bytes())
    middle = len(data) * 6 // 10
    data[middle:middle + 64] = bytes(64)  # image bytes in a chunk: only its CRC tells
    damaged = tmp_path / "damaged.mcap"
    damaged.write_bytes(bytes(data))
    message = error_of(run(dsm_bin, damaged, scene, tmp_path))
    assert message.startswith(f"{damaged} topic /cam0/image_raw message "), message
    assert "its records fail their CRC-32" in message and "its outputs up to there are written" in message
    assert "damaged_input" in json.loads((tmp_path / "run" / "stats.json").read_text())


def test_mcap_message_index_that_lies(dsm_bin, scene, frames, tmp_path):
    """Every message index entry pointed past its chunk's records."""
    mcap = ros2_recording(frames, 10).write_mcap(tmp_path / "ok.mcap", "zstd")
    data = bytearray(mcap.read_bytes())
    at = 0
    while True:  # Message Index records (opcode 7) in the data section: their offsets made huge.
        at = data.find(b"\x07", at + 1)
        if at < 0 or at + 9 > len(data):
            break
        length = struct.unpack_from("<Q", data, at + 1)[0]
        if length == 2 + 4 + 16 * 10 and struct.unpack_from("<I", data, at + 11)[0] == 160:
            for k in range(10):
                struct.pack_into("<Q", data, at + 15 + 16 * k + 8, 1 << 40)
    lying = tmp_path / "lying.mcap"
    lying.write_bytes(bytes(data))
    assert error_of(run(dsm_bin, lying, scene, tmp_path)).startswith(f"{lying} topic /cam0/image_raw message 0")


def test_db3_that_is_not_sqlite(dsm_bin, scene, tmp_path):
    junk = tmp_path / "junk.db3"
    junk.write_bytes(b"not SQLite" * 100)
    assert error_of(run(dsm_bin, junk, scene, tmp_path)) == f"{junk}: not an SQLite file (a ROS 2 bag's .db3 is one)"


def test_bag_folder_with_a_bad_metadata_yaml(dsm_bin, scene, frames, tmp_path):
    bag = ros2_recording(frames, 5).write_sqlite_bag(tmp_path / "bag")
    metadata = bag / "metadata.yaml"
    metadata.write_text(metadata.read_text().replace("storage_identifier: sqlite3", "storage_identifier: leveldb"))
    assert error_of(run(dsm_bin, bag, scene, tmp_path)) == (
        f"{metadata}: storage_identifier 'leveldb' is not one dsm reads (sqlite3, mcap)")
    metadata.write_text(metadata.read_text().replace("  relative_file_paths:\n    - bag_0.db3\n", ""))
    assert error_of(run(dsm_bin, bag, scene, tmp_path)) == f"{metadata}: missing key 'relative_file_paths'"
