# SPDX-License-Identifier: MIT
"""Fixtures of the Python tests: the dsm command (DSM_BIN, set by ctest) and one short synthetic run
shared by the tests that read its outputs."""
import json
import os
import pathlib
import subprocess

import pytest


@pytest.fixture(scope="session")
def dsm_bin():
    path = os.environ.get("DSM_BIN")
    if not path or not os.access(path, os.X_OK):
        pytest.fail("DSM_BIN must name the built dsm executable (ctest sets it)")
    return path


@pytest.fixture(scope="session")
def synthetic_run(dsm_bin, tmp_path_factory):
    """A 320x240 loop of 120 frames, run sequentially: returns (run folder, stats.json)."""
    root = tmp_path_factory.mktemp("synthetic")
    scene, out = root / "scene", root / "run"
    subprocess.run([dsm_bin, "synth", "--scene", "loop", "--frames", "120", "--width", "320", "--height", "240",
                    "--out", str(scene)], check=True, capture_output=True)
    subprocess.run([dsm_bin, "run", str(scene), "--out", str(out), "--sequential", "--quiet"], check=True,
                   capture_output=True)
    return out, json.loads((out / "stats.json").read_text())


@pytest.fixture(scope="session")
def loop(dsm_bin, synthetic_run, tmp_path_factory):
    """The synthetic run's frames (grey arrays), stamps, ground truth and PNG files, and a folder run
    of them without exposure times (a recording carries none), for the recordings' tests:
    (scene, reference run, frames, stamps, poses, pngs)."""
    from recordings import gray_frames, read_tum
    scene = synthetic_run[0].parent / "scene"
    root = tmp_path_factory.mktemp("recordings")
    folder = root / "folder"
    folder.mkdir()
    for name in ["images", "camera.yaml", "groundtruth.tum"]:
        (folder / name).symlink_to(scene / name)
    stamps = [int(line.split()[0]) for line in (scene / "times.txt").read_text().splitlines()
              if line and not line.startswith("#")]
    (folder / "times.txt").write_text("".join(f"{t}\n" for t in stamps))
    run = root / "folder_run"
    subprocess.run([dsm_bin, "run", str(folder), "--out", str(run), "--sequential", "--quiet"], check=True,
                   capture_output=True)
    pngs = sorted((scene / "images").glob("*.png"))
    return scene, run, gray_frames(pngs, 320, 240), stamps, read_tum(scene / "groundtruth.tum"), pngs
