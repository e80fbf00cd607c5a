"""Build-time: what the verifier would find on a candidate reference leader.

``structure_faults``: the workshop findings that refuse a leader (seats, materials, inertials,
strength); ``part_collisions``: per pose, whether the added parts of some bodies fail motion
clearance as ``clearance.collision_fraction`` counts it, so that the joint search can take the union
of candidates' records instead of re-measuring every combination.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np


def structure_faults(path: Path, stock: set[str], grid: np.ndarray) -> list[str]:
    """The verifier's workshop findings that refuse a leader (seats, materials, inertials, strength),
    with spring tensions over ``grid``; parts inside the next link across a joint are not among
    them (they are scored as motion clearance)."""
    from rle_design.mjcf.workshop import workshop_findings
    from rle_tasks.f09_gello.public.gello_helpers import WORKSHOP

    spec = mujoco.MjSpec.from_file(str(path))
    m = spec.compile()
    added = [b for b in range(1, m.nbody) if mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) not in stock]
    others = [b for b in range(1, m.nbody) if b not in set(added)]
    found = workshop_findings(
        spec, m, added, WORKSHOP, poses=grid, baseline=others, fused=added, joint_poses=False
    )
    return [f"{f.code}: {f.message}" for f in found if f.code != "interpenetration.joint"]


def part_collisions(
    design, stock: set[str], names: list[str], poses: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per pose, what ``clearance.collision_fraction`` counts, for the added parts of the bodies
    ``names`` only: whether the pose is counted (the stock arm clear of the table) and whether one of
    those parts fails it (a MuJoCo contact deeper than the verifier's, a spring path first cut by one
    of them, or one inside the next link across a joint) [bool, (N,) each].

    The union of these over a design's parts is the verifier's count for the design (the joint
    search adds candidates' vectors instead of re-measuring every combination)."""
    from rle_design.mjcf.spring_audit import spring_path_faults
    from rle_design.scene import element_ids
    from rle_tasks.f09_gello.clearance import (
        PENETRATION_M,
        TABLE_MARGIN_M,
        _lowest_point,
        clearance_model,
        joint_overlaps,
    )

    m = clearance_model(design)
    d = mujoco.MjData(m)
    every = [b for b in range(1, m.nbody) if mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) not in stock]
    sel = element_ids(m, "body", names)
    mine = np.isin(m.geom_bodyid, sel)
    fixed = [0, *element_ids(m, "body", ("base", "link1"))]
    arm = ~np.isin(m.geom_bodyid, every) & ~np.isin(m.geom_bodyid, fixed)
    geoms = {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g) for g in np.flatnonzero(mine)}
    cut = np.zeros(len(poses), bool)
    for f in spring_path_faults(m, np.asarray(poses, float), every_pose=True):
        cut[f.pose] |= f.element in geoms
    counted, hit = np.zeros(len(poses), bool), np.zeros(len(poses), bool)
    for i, q in enumerate(poses):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        mujoco.mj_collision(m, d)
        if _lowest_point(m, d, arm) < TABLE_MARGIN_M:
            continue
        counted[i] = True
        n = d.ncon
        g1, g2 = d.contact.geom1[:n], d.contact.geom2[:n]
        hit[i] = bool(((d.contact.dist[:n] < -PENETRATION_M) & (mine[g1] | mine[g2])).any()) or cut[i]
    free = np.flatnonzero(counted & ~hit)
    if len(free) and len(sel):
        for k in joint_overlaps(m, sorted(int(b) for b in sel), np.asarray(poses)[free]):
            hit[free[k]] = True
    return counted, hit
