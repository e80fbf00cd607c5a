"""Could the submitted leader be built? Parts fastened, springs mounted and clear, no weightless parts.

Structure rules (each a ``Finding``; any of them skips the submitted-arm battery):

* ``contract.floating_part``: the geoms of each added body form one connected assembly, and the body's
  geometry meets its parent link's (``rle_design.mjcf.buildability``, gap <= ``JOIN_TOL``): a
  counterweight needs a printed arm or bracket that reaches its link;
* ``contract.spring_anchor``: each spring end (tendon site) lies within ``ANCHOR_TOL`` of material of
  its own body (a stock link's surface or an added printed post);
* ``contract.spring_path``: a spring's straight path passes through a part (a link, a servo, an added
  part) at more than ``SPRING_CUT_MAX`` of the public workspace grid; below that, each pose where it
  does counts as a motion-clearance failure (``clearance.py``);
* ``contract.spring_catalog`` / ``contract.spring_push`` / ``contract.spring_overload``: every spring
  is a catalog spring (``rle_design.mjcf.spring_parts``: a tendon's stiffness is a cable-worked
  compression spring's rate, a joint's a torsion spring's), its cable never pushes and its tension
  (or deflection) stays within the rating over the public workspace grid (torsion: the joint range);
* workshop rules (``rle_design.mjcf.workshop``, thresholds in ``public/gello_helpers.py`` as
  ``WORKSHOP``, so the workspace runs the same check): every part of an added body is made of a
  catalog material, its density within that material's range (exact edges): lighter than any is
  ``contract.underweight_part`` (a weightless connector cannot be built), denser than any is
  ``contract.point_mass``, between two ranges ``contract.material_density``; the body's inertial is
  what its geometry gives (``contract.mass_mismatch``, ``contract.com_mismatch``,
  ``contract.com_outside``, ``contract.inertia_mismatch``); no added part shares more than a quarter
  of the smaller part's volume with a part welded to it (``contract.interpenetration``); every printed or metal
  beam (box, cylinder, capsule, mesh) holds its loads (``contract.overstressed_part``) without sagging
  beyond its limit (``contract.flexible_part``). Parts inside the next link across a joint fail
  motion clearance pose by pose (``clearance.py``).
"""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.mjcf.buildability import audit_buildability
from rle_design.mjcf.contract import Finding
from rle_design.mjcf.spring_audit import spring_anchor_faults, spring_path_faults
from rle_design.mjcf.spring_parts import spring_rating_faults
from rle_design.mjcf.workshop import workshop_findings
from rle_tasks.f09_gello.public.gello_helpers import WORKSHOP

JOIN_TOL = 1e-3
"""Largest gap between parts that still counts as fastened [m]: printed parts are modelled touching
or overlapping; 1 mm is below a screw's reach and above the 9-digit XML rounding."""
ANCHOR_TOL = 2e-3
"""Largest gap from a spring site to its body's material [m]: a spring hook's wire is ~1-2 mm."""
SPRING_CUT_MAX = 0.05
"""Fraction of workspace poses at which a spring may cut a part before the leader is refused: the
fraction at which the motion-clearance checkpoint already scores 0 (README)."""
OBJ = mujoco.mjtObj
_WORKSHOP_CODES = {
    "material.too_light": "contract.underweight_part",
    "material.too_dense": "contract.point_mass",
    "material.density": "contract.material_density",
    "interpenetration.weld": "contract.interpenetration",
    "inertial.mass_mismatch": "contract.mass_mismatch",
    "inertial.com_mismatch": "contract.com_mismatch",
    "inertial.com_outside": "contract.com_outside",
    "inertial.inertia_mismatch": "contract.inertia_mismatch",
    "strength.overstressed": "contract.overstressed_part",
    "strength.too_flexible": "contract.flexible_part",
}


def spring_cut_poses(m: mujoco.MjModel, poses: np.ndarray) -> dict[int, str]:
    """Pose index -> message, for each pose where some spring's path passes through a part."""
    out: dict[int, str] = {}
    for f in spring_path_faults(m, np.asarray(poses, float), every_pose=True):
        out.setdefault(f.pose, f.message)
    return out


def buildability_findings(
    spec: mujoco.MjSpec, m: mujoco.MjModel, added: list[int], grid: np.ndarray, path: str
) -> list[Finding]:
    """Structure findings of the build-ability rules above.

    Args:
        spec: The submission's spec (not modified).
        m: Its compiled model.
        added: Ids of the bodies that are not in the stock assembly.
        grid: Public workspace grid [rad], shape (N, dof) (spring tensions at their worst pose).
        path: File the findings refer to.
    """
    out: list[Finding] = []
    names = [mujoco.mj_id2name(m, OBJ.mjOBJ_BODY, b) or f"body{b}" for b in added]
    for d in audit_buildability(m, tol=JOIN_TOL, bodies=names):
        out.append(Finding("contract.floating_part", d.message, element="body", path=path))
    for f in spring_anchor_faults(spec, tol=ANCHOR_TOL):
        out.append(Finding("contract.spring_anchor", f.message, element="site", path=path))
    for r in spring_rating_faults(m, grid):
        out.append(Finding(f"contract.spring_{r.code}", r.message, element="tendon", path=path))
    cuts = spring_cut_poses(m, grid)
    if len(grid) and len(cuts) > SPRING_CUT_MAX * len(grid):
        out.append(
            Finding(
                "contract.spring_path",
                f"spring path through a part at {len(cuts)}/{len(grid)} public grid poses (more than "
                f"{SPRING_CUT_MAX:.0%}); first: {cuts[min(cuts)]}",
                element="tendon",
                path=path,
            )
        )
    stock = [b for b in range(1, m.nbody) if b not in set(added)]
    for f in workshop_findings(
        spec, m, added, WORKSHOP, poses=grid, baseline=stock, fused=added, joint_poses=False
    ):
        if f.code == "interpenetration.joint":
            continue  # across a joint: motion clearance, pose by pose (clearance.py)
        out.append(Finding(_WORKSHOP_CODES[f.code], f.message, element=f.element, path=path))
    return out
