# SPDX-License-Identifier: MIT
"""What the recordings' tests share: a dataset's frames and trajectories as they write them (PNG files
decoded to grey arrays by ffmpeg, TUM rows with their stamps in exact nanoseconds), a run on a
recording, and the check that two runs wrote the same outputs."""
import pathlib
import subprocess
import tempfile

import numpy as np

OUTPUTS = ["frames.tum", "keyframes.tum"]


def seconds_to_ns(text):
    """A decimal seconds string to integer nanoseconds, digit by digit (as dsm reads it)."""
    whole, _, frac = text.partition(".")
    return int(whole) * 10**9 + int((frac + "000000000")[:9])


def read_tum(path):
    """(t_ns, (tx, ty, tz), (qx, qy, qz, qw)) per row of a TUM trajectory file."""
    rows = []
    for line in pathlib.Path(path).read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            f = line.split()
            rows.append((seconds_to_ns(f[0]), tuple(map(float, f[1:4])), tuple(map(float, f[4:8]))))
    return rows


def gray_frames(pngs, width, height):
    """The PNG files' pixels as 8-bit grey arrays, decoded by ffmpeg."""
    with tempfile.NamedTemporaryFile("w", suffix=".txt") as listing:
        listing.write("".join(f"file '{pathlib.Path(p).resolve()}'\n" for p in pngs))
        listing.flush()
        raw = subprocess.run(["ffmpeg", "-v", "error", "-f", "concat", "-safe", "0", "-i", listing.name, "-fps_mode", "passthrough", "-f",
                              "rawvideo", "-pix_fmt", "gray", "-"], capture_output=True, check=True).stdout
    frames = np.frombuffer(raw, np.uint8).reshape(-1, height, width)
    assert len(frames) == len(pngs), f"ffmpeg decoded {len(frames)} of {len(pngs)} frames"
    return frames


def run_recording(dsm_bin, recording, out, *args):
    """`dsm run` on a recording, sequential; its output folder."""
    result = subprocess.run([dsm_bin, "run", str(recording), "--out", str(out), "--sequential", "--quiet", *args],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return out


def assert_same_outputs(run, reference, with_eval=True):
    for name in OUTPUTS + (["eval.json"] if with_eval else []):
        assert (run / name).read_bytes() == (reference / name).read_bytes(), name
