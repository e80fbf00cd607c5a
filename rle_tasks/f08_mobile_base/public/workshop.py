"""Workshop check of a base before submitting it: the verifier's own rules for parts inside parts and
for inertials that do not match their geometry.

python -m mobile_base.workshop robot.xml

Every part of a base is welded to the chassis, so MuJoCo never collides one with another: a battery
or an adapter sunk into a profile, or two profiles of different bodies crossing, is found here
(``f08.interpenetration``, collision-geometry penetration deeper than 0.5 mm with shared material).
The chassis' inertial must be what its geoms give (``f08.inertial_mismatch``: mass within 0.1 %,
centre of mass within 1 mm and inside the geometry, inertia within 1 %). Profiles' masses are
checked against the profile catalog by the verifier's catalog rules (kg/m), not by a material
density.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import mujoco

from rle_design.mjcf import load_design
from rle_design.mjcf.contract import Finding
from rle_design.mjcf.material_mass import InertialTolerance
from rle_design.mjcf.workshop import WorkshopRules, workshop_findings

from .scene import CHASSIS

WORKSHOP = WorkshopRules(
    joint_tol=1e-4,
    weld_tol=5e-4,
    shared_volume=1e-9,
    inertial=InertialTolerance(mass_rtol=1e-3, com_tol=1e-3, inertia_rtol=0.01),
    materials=None,
    strength=False,
)
"""The verifier's thresholds (README, "Thresholds"): welded parts may meet with 0.5 mm of penetration
(positions are written to 0.1 mm; a bolted face measures 0.0 mm) and 1 mm^3 of shared material."""
CODES = {
    "interpenetration.weld": "f08.interpenetration",
    "interpenetration.joint": "f08.interpenetration",
    "inertial.mass_mismatch": "f08.inertial_mismatch",
    "inertial.com_mismatch": "f08.inertial_mismatch",
    "inertial.com_outside": "f08.inertial_mismatch",
    "inertial.inertia_mismatch": "f08.inertial_mismatch",
}


def workshop_findings_of(spec: mujoco.MjSpec, model: mujoco.MjModel) -> list[Finding]:
    """Findings of the base's bodies: every pair of parts of different bodies, the chassis' inertial
    (catalog parts keep their fragments' inertials, compared by the verifier's catalog rules)."""
    chassis = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, CHASSIS)
    bodies = list(range(1, model.nbody))
    found = workshop_findings(spec, model, bodies, WORKSHOP)
    out = [Finding(CODES[f.code], f.message, element=f.element) for f in found if f.code.startswith("interp")]
    if chassis >= 0:
        own = [
            f.message
            for f in workshop_findings(spec, model, [chassis], WORKSHOP)
            if f.code.startswith("inertial.")
        ]
        if own:  # one finding for the chassis, every disagreement named
            out.append(Finding("f08.inertial_mismatch", "; ".join(own), element="body"))
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m mobile_base.workshop", description=__doc__.splitlines()[0])
    p.add_argument("robot", nargs="?", default="robot.xml", help="the base's MJCF (default robot.xml)")
    a = p.parse_args(argv)
    robot = Path(a.robot)
    design = load_design(robot.parent, entry=robot.name)
    found = workshop_findings_of(design.fresh_spec(), design.compile())
    for f in found:
        print(f"{f.code}: {f.message}")
    print("workshop check passed" if not found else f"{len(found)} finding(s)")
    return 1 if found else 0


if __name__ == "__main__":
    raise SystemExit(main())
