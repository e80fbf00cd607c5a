"""Preview a base with an arm, the payload and the shelf as the evaluator builds them.

python -m mobile_base.preview robot.xml --arm panda --payload 1 --png preview.png
"""

from __future__ import annotations

import argparse
from pathlib import Path

from rle_design.mjcf import load_design
from rle_design.scene import arm_ids
from rle_design.viz.render import render_png

from .scene import build_scene


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m mobile_base.preview", description=__doc__.splitlines()[0])
    p.add_argument("robot", nargs="?", default="robot.xml", help="the base's MJCF (default robot.xml)")
    p.add_argument("--arm", default="panda", choices=arm_ids())
    p.add_argument("--payload", type=int, default=1, choices=[0, 1, 2], help="payload [kg]")
    p.add_argument("--png", default="preview.png", help="output image")
    a = p.parse_args(argv)
    robot = Path(a.robot)
    design = load_design(robot.parent, entry=robot.name)
    scene = build_scene(design.fresh_spec, a.arm, a.payload, shelf=True)
    actuators = [scene.model.actuator(i).name for i in range(scene.model.nu)]
    print(f"base + arm + payload mass {scene.mass:.2f} kg; actuators {actuators}")
    render_png(scene.model, scene.rest_data(), a.png, lookat=[0.5, 0, 0.5], distance=2.4)
    print(f"wrote {a.png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
