# SPDX-License-Identifier: MIT
"""map.ply and keyframes.ply of a run, read back by plyread (not dsm's code) and checked against
the run's stats.json and trajectory."""
import subprocess

import numpy as np

from plyread import read_ply


def test_map_points_match_stats(synthetic_run):
    out, stats = synthetic_run
    points = read_ply(out / "map.ply")
    first_map = stats["maps"][0]
    assert len(points) == first_map["map_points"] == stats["map_points"]
    assert len(points) > 1000
    xyz = np.stack([points["x"], points["y"], points["z"]], axis=1)
    assert np.all(np.isfinite(xyz))
    np.testing.assert_allclose(xyz.min(axis=0), first_map["bounds"]["min"], rtol=0, atol=1e-6)
    np.testing.assert_allclose(xyz.max(axis=0), first_map["bounds"]["max"], rtol=0, atol=1e-6)
    assert np.all(points["red"] == points["green"]) and np.all(points["green"] == points["blue"])
    assert points["red"].std() > 5  # Textured scene: grey values vary.
    assert points["host"].min() >= 0 and points["host"].max() < stats["keyframes"]
    assert points["observations"].min() >= 0
    assert points["observations"].mean() >= 1  # Mapped points are seen from other keyframes.


def test_keyframe_centres_match_trajectory(synthetic_run):
    out, stats = synthetic_run
    keyframes = read_ply(out / "keyframes.ply")
    assert len(keyframes) == stats["keyframes"]
    assert list(keyframes["keyframe"]) == list(range(stats["keyframes"]))
    assert np.all(np.diff(keyframes["frame"]) > 0)
    tum = np.loadtxt(out / "keyframes.tum")
    centres = np.stack([keyframes["x"], keyframes["y"], keyframes["z"]], axis=1)
    np.testing.assert_allclose(centres, tum[:, 1:4], rtol=0, atol=1e-5)


def test_no_map_writes_no_ply(dsm_bin, synthetic_run, tmp_path):
    out, _ = synthetic_run
    scene = out.parent / "scene"
    run = tmp_path / "run"
    subprocess.run([dsm_bin, "run", str(scene), "--out", str(run), "--sequential", "--quiet", "--end", "30",
                    "--no-map"], check=True, capture_output=True)
    assert (run / "keyframes.tum").exists()
    assert not (run / "map.ply").exists() and not (run / "keyframes.ply").exists()
