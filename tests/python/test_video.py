# SPDX-License-Identifier: MIT
"""Video input: the synthetic run's PNG frames encoded as H.264 by Debian's ffmpeg (crf 8: the
issue compares tracking, compression aside), run by dsm from the mp4 with the scene's camera.yaml,
and evaluated against the scene's ground truth."""
import json
import shutil
import subprocess


def test_mp4_tracks_as_well_as_its_png_frames(dsm_bin, synthetic_run, tmp_path):
    assert shutil.which("ffmpeg"), "ffmpeg missing (scripts/setup.sh installs it)"
    out, stats = synthetic_run
    scene = out.parent / "scene"
    video = tmp_path / "scene.mp4"
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-framerate", "20", "-i", str(scene / "images" / "%06d.png"),
                    "-c:v", "libx264", "-crf", "8", "-pix_fmt", "yuv420p", str(video)], check=True)
    # The container's clock starts at 0; the scene's at its first stamp.
    first_ns = next(int(line.split()[0]) for line in (scene / "times.txt").read_text().splitlines()
                    if line and not line.startswith("#"))
    offset = f"{first_ns // 10**9}.{first_ns % 10**9:09d}"
    run = tmp_path / "run"
    result = subprocess.run([dsm_bin, "run", str(video), "--calib", str(scene / "camera.yaml"), "--groundtruth",
                             str(scene / "groundtruth.tum"), "--time-offset", offset, "--sequential", "--quiet",
                             "--out", str(run)], check=True, capture_output=True, text=True)
    video_stats = json.loads((run / "stats.json").read_text())
    assert video_stats["frames"] == stats["frames"] == 120
    assert video_stats["frames_tracked"] == 120
    png_ate = json.loads((out / "eval.json").read_text())["keyframes"]["ape"]["rmse"]
    video_ate = json.loads((run / "eval.json").read_text())["keyframes"]["ape"]["rmse"]
    print(f"keyframe ATE: PNG {1000 * png_ate:.2f} mm, mp4 {1000 * video_ate:.2f} mm")
    assert video_ate <= 1.5 * png_ate, result.stdout


def test_unreadable_video_is_a_clear_error(dsm_bin, synthetic_run, tmp_path):
    scene = synthetic_run[0].parent / "scene"
    junk = tmp_path / "junk.mkv"
    junk.write_bytes(b"\x1a\x45\xdf\xa3" + bytes(2000))
    result = subprocess.run([dsm_bin, "run", str(junk), "--calib", str(scene / "camera.yaml"), "--out",
                             str(tmp_path / "run")], capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr.strip() == f"dsm: error: {junk}: cannot open as a video (not a video file, or damaged)"
