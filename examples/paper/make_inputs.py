# SPDX-License-Identifier: LGPL-2.1-only
"""Writes the recorded inputs of the paper experiments (deterministic, numpy only).

Usage: /usr/bin/python3 examples/paper/make_inputs.py <folder> <E1 frames> <E2 seconds>
                                                       <E3 frames> <E4 frames>

  e1.rgb     224x224 RGB frames             e3.rgb   160x120 RGB frames
  e4.rgb     640x360 RGB frames             e2.rgb   128x128 RGB frames at 30 fps
  e2.s16     16 kHz mono signed 16-bit PCM  e2.imu   6 float32 channels at 100 Hz
Video frames are a dark noisy background with two bright discs moving across it (the
"faces"/"objects" the detectors of make_models.py react to); in e3.rgb the discs are absent
from 4 frames in every 16 (frames without a face). Raw files are what filesrc +
rawvideoparse/rawaudioparse read in the pipelines and what the Control programs read by hand.
"""

import os
import sys

import numpy as np


def clip(path, frames, w, h, seed, gaps=False):
    """gaps: no disc in frames 12..15 of every 16 (E3: frames without a face)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:h, 0:w]
    base = rng.integers(0, 60, size=(h, w, 3), dtype=np.uint8)
    r = max(6, h // 8)
    with open(path, "wb") as f:
        for i in range(frames):
            img = base.copy()
            t = i / 30.0
            if gaps and i % 16 >= 12:
                f.write(img.tobytes())
                continue
            for k, (sx, sy, col) in enumerate([(0.23, 0.17, (250, 240, 230)),
                                              (-0.13, 0.29, (230, 250, 200))]):
                cx = (0.5 + 0.4 * np.sin(2 * np.pi * sx * t + k)) * w
                cy = (0.5 + 0.35 * np.cos(2 * np.pi * sy * t + 2 * k)) * h
                m = (xx - cx) ** 2 + (yy - cy) ** 2 <= (r * (1 + 0.5 * k)) ** 2
                img[m] = col
            f.write(img.tobytes())


def main():
    out = sys.argv[1]
    n1, secs2, n3, n4 = (int(v) for v in sys.argv[2:6])
    os.makedirs(out, exist_ok=True)
    p = lambda name: os.path.join(out, name)  # noqa: E731
    clip(p("e1.rgb"), n1, 224, 224, 1)
    clip(p("e2.rgb"), 30 * secs2, 128, 128, 2)
    clip(p("e3.rgb"), n3, 160, 120, 3, gaps=True)
    clip(p("e4.rgb"), n4, 640, 360, 4)
    rng = np.random.default_rng(5)
    t = np.arange(16000 * secs2) / 16000.0
    pcm = 6000 * np.sin(2 * np.pi * 440 * t) * (0.5 + 0.5 * np.sin(2 * np.pi * 0.5 * t))
    pcm += rng.normal(0, 800, size=t.shape)
    pcm.astype("<i2").tofile(p("e2.s16"))
    ti = np.arange(100 * secs2) / 100.0
    imu = np.stack([np.sin(2 * np.pi * f * ti + k) for k, f in enumerate([1, 2, 0.5, 3, 1.5, 0.7])],
                   axis=1) + rng.normal(0, 0.05, size=(ti.size, 6))
    imu.astype("<f4").tofile(p("e2.imu"))


if __name__ == "__main__":
    main()
