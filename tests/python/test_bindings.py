# SPDX-License-Identifier: MIT
"""The Python module: the README's example as written, System against the command line, errors."""
import json
import os
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

import dsm

README = pathlib.Path(__file__).resolve().parents[2] / "README.md"


def readme_example():
    text = README.read_text()
    match = re.search(r"<!-- python-example -->\s*```python\n(.*?)```", text, re.S)
    assert match, "README.md has no python-example block"
    return match.group(1)


def test_readme_example_runs_as_written(dsm_bin, tmp_path):
    subprocess.run([dsm_bin, "synth", "--scene", "loop", "--frames", "100", "--width", "320", "--height", "240",
                    "--out", str(tmp_path / "demo_out" / "loop")], check=True, capture_output=True)
    code = readme_example()
    assert len(code.strip().splitlines()) <= 12
    env = dict(os.environ)
    result = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    first, second = result.stdout.strip().splitlines()
    keyframe_shape, points_shape = re.findall(r"\((\d+), (\d+)\)", first)
    assert int(keyframe_shape[0]) > 5 and keyframe_shape[1] == "8"
    assert int(points_shape[0]) > 1000 and points_shape[1] == "3"
    tracked, ate = second.split()
    assert int(tracked) == 100
    assert float(ate) < 0.005  # metres
    assert (tmp_path / "demo_out" / "py_run" / "report.html").exists()


def test_system_gives_what_the_command_line_gives(synthetic_run):
    out, stats = synthetic_run
    dataset = dsm.read_dataset(str(out.parent / "scene"))
    assert len(dataset) == 120 and dataset.format == "folder"
    assert dataset.ground_truth.shape == (120, 8)
    system = dsm.System(dataset.camera)
    reports = [system.process(frame.t_ns, frame.image) for frame in dataset]
    system.finish()
    # Keyframe 0 (the start's first frame) is made by the frame that starts the map, which reports keyframe 1.
    assert sum(r["keyframe"] for r in reports) == stats["keyframes"] - 1
    keyframes = system.keyframe_trajectory()
    cli = np.loadtxt(out / "keyframes.tum")
    assert keyframes.shape == cli.shape
    np.testing.assert_allclose(keyframes[:, 1:], cli[:, 1:], rtol=0, atol=1e-8)  # Same run, printed to 9 decimals.
    np.testing.assert_allclose(keyframes[:, 0], cli[:, 0], rtol=0, atol=1e-6)
    assert system.frame_trajectory().shape == (stats["frames_tracked"], 8)
    assert system.map_points().shape == (stats["map_points"], 3)


def test_system_starts_a_second_map_after_a_cut_and_merges_it(dsm_bin, tmp_path):
    """`forward` with frames 60-129 cut out: the camera reappears beyond the map, relocalisation keeps
    failing and a second map starts; on the way back it recognises the first and takes it in. Fed
    frame by frame, dsm.System ends with the trajectories `dsm run --sequential` writes."""
    scene, out = tmp_path / "scene", tmp_path / "cli"
    subprocess.run([dsm_bin, "synth", "--scene", "forward", "--turned-textures", "--defects", "cut:60-129",
                    "--out", str(scene)], check=True, capture_output=True)
    subprocess.run([dsm_bin, "run", str(scene), "--out", str(out), "--sequential", "--quiet", "--no-report"],
                   check=True, capture_output=True)
    stats = json.loads((out / "stats.json").read_text())
    assert len(stats["maps_merged"]) == 1 and len(stats["maps"]) == 2
    dataset = dsm.read_dataset(str(scene))
    system = dsm.System(dataset.camera)
    reports = [system.process(frame.t_ns, frame.image, frame.exposure_ms) for frame in dataset]
    system.finish()
    assert {r["map"] for r in reports if r["status"] == "ok"} == {0, 1}
    for name, trajectory in (("keyframes.tum", system.keyframe_trajectory()),
                             ("frames.tum", system.frame_trajectory())):
        cli = np.loadtxt(out / name)
        assert trajectory.shape == cli.shape, name
        np.testing.assert_allclose(trajectory[:, 1:], cli[:, 1:], rtol=0, atol=1e-8)
        np.testing.assert_allclose(trajectory[:, 0], cli[:, 0], rtol=0, atol=1e-6)
    with pytest.raises(dsm.InputError, match="no map 1"):
        system.keyframe_trajectory(map=1)  # Taken in by map 0.


def test_run_returns_the_stats(synthetic_run, tmp_path):
    out, _ = synthetic_run
    stats = dsm.run(str(out.parent / "scene"), out=str(tmp_path / "run"), end=40, write_report=False,
                    options={"window": {"temporal_keyframes": 5}})
    assert stats["frames"] == 40 and stats["pace"] == "sequential"
    assert stats == {**json.loads((tmp_path / "run" / "stats.json").read_text()), "eval": stats["eval"]}
    assert not (tmp_path / "run" / "report.html").exists()


def test_run_saves_and_loads_maps(synthetic_run, tmp_path):
    out, _ = synthetic_run
    scene = str(out.parent / "scene")
    first = dsm.run(scene, out=str(tmp_path / "s1"), end=60, write_report=False, save_map=str(tmp_path / "a.dsmmap"))
    assert first["map_saved"]["keyframes"] == first["keyframes"]
    second = dsm.run(scene, out=str(tmp_path / "s2"), start=60, write_report=False,
                     load_map=str(tmp_path / "a.dsmmap"))
    assert second["map_loaded"]["keyframes"] == first["keyframes"]
    assert 60 <= second["relocalised_in_loaded_map_at_frame"] <= 63
    with pytest.raises(dsm.InputError, match="nothing.dsmmap"):
        dsm.run(scene, out=str(tmp_path / "s3"), load_map=str(tmp_path / "nothing.dsmmap"))

    # The same through Map and System: read, written again byte for byte, taken up by a System that
    # relocalises in it and extends it.
    saved = dsm.load_map(str(tmp_path / "a.dsmmap"))
    assert saved.maps == 1 and saved.keyframes == first["keyframes"]
    assert saved.points == first["map_points"]
    saved.save(str(tmp_path / "b.dsmmap"))
    assert (tmp_path / "b.dsmmap").read_bytes() == (tmp_path / "a.dsmmap").read_bytes()
    dataset = dsm.read_dataset(scene)
    system = dsm.System(dataset.camera, map=saved)
    reports = [system.process(dataset[i].t_ns, dataset[i].image) for i in range(60, 90)]
    first_ok = next(r["index"] for r in reports if r["status"] == "ok")
    assert first_ok <= 3  # The fourth frame at the latest (indices count from the System's first frame).
    assert sum(r["keyframe"] for r in reports) > 0
    system.save_map(str(tmp_path / "c.dsmmap"))
    assert dsm.load_map(str(tmp_path / "c.dsmmap")).keyframes > saved.keyframes
    with pytest.raises(dsm.InputError, match="save_map"):
        system.process(dataset[90].t_ns, dataset[90].image)

    # Localising in it (localize=True): tracked the same way, the map given back as it was loaded.
    local = dsm.System(dataset.camera, map=saved, localize=True)
    reports = [local.process(dataset[i].t_ns, dataset[i].image) for i in range(60, 90)]
    assert next(r["index"] for r in reports if r["status"] == "ok") <= 3
    local.save_map(str(tmp_path / "d.dsmmap"))
    assert (tmp_path / "d.dsmmap").read_bytes() == (tmp_path / "a.dsmmap").read_bytes()
    localized = dsm.run(scene, out=str(tmp_path / "s4"), start=60, write_report=False,
                        load_map=str(tmp_path / "a.dsmmap"), localize=True, save_map=str(tmp_path / "e.dsmmap"))
    assert localized["localize"] and 60 <= localized["relocalised_in_loaded_map_at_frame"] <= 63
    assert (tmp_path / "e.dsmmap").read_bytes() == (tmp_path / "a.dsmmap").read_bytes()
    with pytest.raises(dsm.InputError, match="localize"):
        dsm.System(dataset.camera, localize=True)


def test_bad_input_raises_with_dsm_message(synthetic_run, tmp_path):
    out, _ = synthetic_run
    with pytest.raises(dsm.InputError, match="no_such_folder"):
        dsm.read_dataset(str(tmp_path / "no_such_folder"))
    camera = {"width": 320, "height": 240, "fx": 192.0, "fy": 192.0, "cx": 159.5, "cy": 119.5}
    with pytest.raises(ValueError, match="window.nope"):
        dsm.System(camera, {"window": {"nope": 1}})
    with pytest.raises(ValueError, match="camera"):
        dsm.System({"width": 320})
    system = dsm.System(camera)
    with pytest.raises(ValueError, match=r"\(240, 320\)"):
        system.process(0, np.zeros((10, 10)))
    with pytest.raises(ValueError, match="pace"):
        dsm.run(str(out.parent / "scene"), out=str(tmp_path / "x"), pace="fast")
    # uint8 images are taken as grey values too.
    assert system.process(0, np.full((240, 320), 128, np.uint8))["status"] == "initializing"
    # Frames come in time order: a timestamp that does not increase is refused, and changes nothing.
    with pytest.raises(ValueError, match="must come in time order"):
        system.process(0, np.full((240, 320), 128, np.uint8))
    with pytest.raises(ValueError, match="must come in time order"):
        system.process(-5, np.full((240, 320), 128, np.uint8))
    assert system.process(1, np.full((240, 320), 128, np.uint8))["index"] == 1
