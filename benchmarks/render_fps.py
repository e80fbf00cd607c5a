"""Offscreen RGB-D frames per second on CPU for a simple 128x128 scene (target: >= 200 frames/s).

Usage: ``.venv/bin/python benchmarks/render_fps.py [--frames N] [--size PX]``. Prints one line per
configuration: fast RGB-D (one draw, colour + depth), fast RGB-D + segmentation (two draws) and the
default-quality RGB-D (shadows, 4x MSAA) for comparison. Exit status 1 if fast RGB-D misses 200 fps.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402

from rle_design.sensors import RgbdSensor  # noqa: E402

SCENE = """
<mujoco>
  <visual><global offwidth="{n}" offheight="{n}"/></visual>
  <worldbody>
    <light pos="0 0 3" dir="0 0 -1"/>
    <geom name="floor" type="plane" size="2 2 0.1" rgba="0.6 0.6 0.6 1"/>
    <geom name="box" type="box" size="0.1 0.1 0.1" pos="0 0 0.1" rgba="0.8 0.2 0.2 1"/>
    <geom name="ball" type="sphere" size="0.05" pos="0.25 0.1 0.05" rgba="0.2 0.2 0.8 1"/>
    <camera name="cam" pos="0.8 -0.8 0.8" xyaxes="0.707 0.707 0 -0.4 0.4 0.82" fovy="50"/>
  </worldbody>
</mujoco>
"""


def measure(n: int, frames: int, *, fast: bool, segmentation: bool) -> float:
    """Frames per second of ``RgbdSensor.render`` after a short warm-up."""
    model = mujoco.MjModel.from_xml_string(SCENE.format(n=n))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with RgbdSensor(model, "cam", n, n, fast=fast, segmentation=segmentation) as sensor:
        for _ in range(10):
            sensor.render(data)
        t0 = time.perf_counter()
        for _ in range(frames):
            sensor.render(data)
        return frames / (time.perf_counter() - t0)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--frames", type=int, default=500)
    p.add_argument("--size", type=int, default=128)
    args = p.parse_args()
    print(f"backend MUJOCO_GL={os.environ['MUJOCO_GL']}, {args.size}x{args.size}, {args.frames} frames")
    fast = measure(args.size, args.frames, fast=True, segmentation=False)
    print(f"fast RGB-D                 {fast:8.0f} frames/s")
    seg = measure(args.size, args.frames, fast=True, segmentation=True)
    print(f"fast RGB-D + segmentation  {seg:8.0f} frames/s")
    slow = measure(args.size, max(20, args.frames // 10), fast=False, segmentation=False)
    print(f"default quality RGB-D      {slow:8.0f} frames/s")
    return 0 if fast >= 200 else 1


if __name__ == "__main__":
    sys.exit(main())
