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
