"""Public harness of ``08-mobile-base``: instruction and the development workspace layout."""

from __future__ import annotations

import shutil
from pathlib import Path

from rle_design.catalog import load_catalog
from rle_design.paths import CATALOG_DIR, resolve_asset

SKELETON = Path(__file__).resolve().parent / "assets" / "skeleton_robot.xml"
"""Workspace skeleton (written by ``solutions/design_gen.py``)."""

INSTRUCTION = """# 08-mobile-base: universal mobile-manipulator base

Design and build ONE mecanum mobile base, and its controller, for three canonical arms: Franka Panda
(7 DoF), Universal Robots UR5e (6 DoF) and UFACTORY xArm7 (7 DoF). The same chassis, battery, wheels
and `arm_mount_site` are used unchanged with every arm. Units are SI (m, kg, s, rad, N).

## Submit (a directory)
- `robot.xml` (MJCF): one root body `chassis` with a `<freejoint/>` and no other joint, no actuator,
  no equality, no gravcomp. Inside it:
  - bodies `wheel_fl`, `wheel_fr`, `wheel_rl`, `wheel_rr` (front = +x, left = +y), each carrying the
    catalog part `parts/mecanum_wheel.xml` unchanged (inertial and cylinder), aligned with the chassis
    (axle along y). The evaluator installs the drive: a velocity-controlled motor per wheel (command =
    wheel speed, rad/s, |.| <= 20, torque <= 12 N m) and the roller contact with the floor.
  - body `battery` = `parts/battery.xml` unchanged; body `universal_adapter` =
    `parts/universal_adapter.xml` unchanged, with site `arm_mount_site` at its top centre
    (pos 0 0 0.015 in the adapter frame, z up). Every arm is attached at that site.
  - wheel drive convention: each wheel transmits force only along its roller axis s (chassis frame):
    fl and rr s = (1, -1)/sqrt2, fr and rl s = (1, 1)/sqrt2; for a chassis twist (vx, vy, wz) the
    wheel speed is omega_i = sqrt2 * ((vx - wz*y_i, vy + wz*x_i) . s_i) / r, with (x_i, y_i) the
    wheel position in the chassis frame and r = 0.0762 m (pure forward motion: omega = vx / r).
  - structure: only aluminium profiles of `catalog/profiles.yaml`, each a box geom named
    `profile_<id>_<anything>` whose two smaller full sizes equal the catalog section and whose
    explicit `mass` equals length x kg/m (within 2 %). Other geoms must not collide (contype =
    conaffinity = 0) and carry no mass. Only the wheels may touch the floor.
- `controller.py`: plain Python (numpy, mujoco, pinocchio and the `rle_design` toolkit are importable;
  the verifier package `rle_tasks` is not), run in a sandbox with a 30 s cap per call and its own
  working directory holding a copy of your `robot.xml`:
  - `reset(arm: str, target: ndarray(3), payload_kg: float, layout: dict) -> None` once per trial;
    `layout` gives actuator names and order, the qpos/qvel addresses of the chassis, wheels and arm.
  - `control(t, qpos, qvel, ctrl) -> ndarray(nu)` at 50 Hz: one finite command per actuator (wheel
    speeds [rad/s], arm joint torques [N m]); commands are clipped to the actuator ranges. An
    exception, a timeout, a non-finite or wrongly shaped command fails the trial with its message.

## Shelf (catalog/shelf.yaml)
The base starts at rest at the origin facing +x, arm in its stowed posture, payload fixed at the tool.
The shelf face is the plane x = 1.10 m; boards at 0.40, 0.70, 1.00 m. Twelve targets (T01..T12) are
tool-site positions; a trial succeeds when the tool stays within the tolerance for the hold time,
without any robot contact with the shelf, without tipping and without a sustained loss of wheel
support. All 12 targets count, for each arm, with 1 kg and with 2 kg.

## Credit (minimum over the three arms at each checkpoint)
| checkpoint | weight |
|---|---|
| validity (contract, catalog, immutable parts, mount usable by all arms, no interpenetration) | 15 % |
| design / resources (footprint, height, base mass, profile length and cost: smaller is better) | 35 % |
| static stability (stowed, reach extremes and the targets, 0/1/2 kg: margin, force angle, wheel load) | 15 % |
| dynamic stability (base accelerations, emergency stop, turning in place, arm swings with 2 kg) | 20 % |
| shelf integration, 1 kg | 10 % |
| shelf integration, 2 kg | 5 % |

A failed validity checkpoint, or a failed required load (a pose in which the machine cannot stand
with 1 kg, or fewer than half of the targets held with 1 kg by some arm), caps the reward at 0.15. The evaluation varies physical details (target positions by up to a
centimetre, payload centre of mass, floor friction).

## Workspace
`arms/` canonical arm models, `catalog/` profiles, parts and shelf, `preview/` a preview scene and
`preview.py` (`python preview.py robot.xml --arm panda --png out.png`: the base with the verifier's
wheel model, an arm, the payload and the shelf), `skeleton_robot.xml` (the required bodies, parts
and site with one example profile; not a working design).
"""


def make_dev_env(workspace: Path) -> None:
    """Lay out the development workspace (arms, catalog, preview)."""
    ws = Path(workspace)
    (ws / "catalog" / "parts").mkdir(parents=True, exist_ok=True)
    for name in ("profiles.yaml", "parts.yaml", "shelf.yaml"):
        shutil.copyfile(CATALOG_DIR / name, ws / "catalog" / name)
    for part in load_catalog("parts"):
        shutil.copyfile(CATALOG_DIR / part.fragment, ws / "catalog" / part.fragment)
    for arm in load_catalog("arms"):
        src = resolve_asset(arm.model).parent
        shutil.copytree(src, ws / "arms" / arm.id, dirs_exist_ok=True)
    (ws / "instruction.md").write_text(INSTRUCTION)
    shutil.copyfile(SKELETON, ws / "skeleton_robot.xml")
    (ws / "preview.py").write_text(_PREVIEW)


_PREVIEW = '''"""Preview the base with an arm and the shelf: python preview.py robot.xml --arm panda --png out.png"""
import argparse
from pathlib import Path

import mujoco
from rle_design.mjcf import load_design
from rle_design.viz.render import render_png
from rle_tasks.f08_mobile_base.scene import build_scene

p = argparse.ArgumentParser()
p.add_argument("robot", default="robot.xml")
p.add_argument("--arm", default="panda", choices=["panda", "ur5e", "xarm7"])
p.add_argument("--payload", type=int, default=1, choices=[0, 1, 2])
p.add_argument("--png", default="preview.png")
a = p.parse_args()
d = load_design(Path(a.robot).parent, entry=Path(a.robot).name)
sc = build_scene(d.fresh_spec, a.arm, a.payload, shelf=True)
data = sc.rest_data()
print("base+arm mass", round(sc.mass, 2), "kg; actuators", [sc.model.actuator(i).name for i in range(sc.model.nu)])
render_png(sc.model, data, a.png, lookat=[0.5, 0, 0.5], distance=2.4)
print("wrote", a.png)
'''
