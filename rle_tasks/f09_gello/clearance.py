"""Motion clearance: do the added parts collide with the arm, the base or the table over the workspace?

The submitted leader is recompiled with every geom colliding (``contype = conaffinity = 1``, no
margin, every ``<exclude>`` removed, so a part cannot opt out) and a table plane at z = 0 (the bottom
of the base plate). A grid pose counts as a clearance failure when a geom of an added body
penetrates any geom of another rigid group in MuJoCo's collision, when an added part shares material
with a geom of the neighbouring link across a joint beyond what the stock joint itself shares
(``rle_design.mjcf.interpenetration``: MuJoCo's contact filter skips parent/child pairs; penetration
deeper than ``PENETRATION_M`` with more than ``WORKSHOP.shared_volume`` of added shared material), or when a
spring's straight path passes through a part (``buildable.spring_cut_poses``). Poses where the stock arm
itself (beyond link 1, which sits on the base plate) comes within ``TABLE_MARGIN_M`` of the table are
not working poses and are not counted.
"""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np

from rle_design.mjcf.interpenetration import Overlap, find_overlaps
from rle_design.mjcf.loader import Design
from rle_design.scene import element_ids
from rle_tasks.f09_gello.buildable import spring_cut_poses
from rle_tasks.f09_gello.public.gello_helpers import WORKSHOP

PENETRATION_M = WORKSHOP.joint_tol
"""Penetration of the collision geometry that counts as a collision [m] (0.1 mm, README)."""
TABLE_MARGIN_M = 0.03
"""Poses that bring the stock arm (beyond link 1) this close to the table are not counted [m]."""


def clearance_model(design: Design) -> mujoco.MjModel:
    """Compiled copy of the design with all geoms colliding and a table plane."""
    spec = design.fresh_spec()
    for g in spec.geoms:
        g.contype = 1
        g.conaffinity = 1
        g.margin = 0.0
        g.gap = 0.0
    for e in list(spec.excludes):  # a submitted <exclude> cannot hide a collision
        spec.delete(e)
    spec.worldbody.add_geom(name="__table__", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[2.0, 2.0, 0.1])
    return spec.compile()


def joint_overlaps(m: mujoco.MjModel, added: list[int], poses: np.ndarray) -> dict[int, Overlap]:
    """Pose index -> the first overlap of an added part with the next link across a joint there."""
    stock = [b for b in range(1, m.nbody) if b not in set(added)]
    found = find_overlaps(
        m,
        added,
        poses,
        joint_tol=PENETRATION_M,
        weld_tol=np.inf,  # welded seats: buildable.py, at the zero pose
        fused=added,
        baseline=stock,
        volume_tol=WORKSHOP.shared_volume,
        first_per_pose=True,
    )
    return {o.pose: o for o in found}


def collision_fraction(
    design: Design, added_bodies: list[str], poses: np.ndarray
) -> tuple[float, list[str], list[Overlap]]:
    """Fraction of poses with an added part in collision, up to five example pairs, and the overlaps
    across a joint (one per pose at which one is the only failure; ``Overlap.pose`` indexes
    ``poses``).

    Args:
        design: Loaded submission.
        added_bodies: Names of the bodies that are not in the stock assembly.
        poses: Grid poses [rad], shape (N, n).
    """
    if len(poses) == 0:
        return 0.0, [], []
    m = clearance_model(design)
    d = mujoco.MjData(m)
    added = set(element_ids(m, "body", added_bodies))
    geom_added = np.isin(m.geom_bodyid, list(added))
    fixed = [0, *element_ids(m, "body", ("base", "link1"))]
    stock_arm = ~geom_added & ~np.isin(m.geom_bodyid, fixed)  # stock parts that can reach the table
    cuts = spring_cut_poses(m, poses)  # a spring's path through a part fails the pose too
    hits, counted, examples = 0, 0, []
    open_poses: list[int] = []  # counted poses that nothing above fails
    for i, q in enumerate(poses):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        mujoco.mj_collision(m, d)
        if _lowest_point(m, d, stock_arm) < TABLE_MARGIN_M:
            continue  # the stock arm itself scrapes the table: not a working pose
        n = d.ncon
        dist, g1, g2 = d.contact.dist[:n], d.contact.geom1[:n], d.contact.geom2[:n]
        deep = dist < -PENETRATION_M
        counted += 1
        hit = deep & (geom_added[g1] | geom_added[g2])
        bad = bool(hit.any())
        if bad and len(examples) < 5:
            k = int(np.flatnonzero(hit)[0])
            n1 = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, int(g1[k])) or f"geom{g1[k]}"
            n2 = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, int(g2[k])) or f"geom{g2[k]}"
            examples.append(f"{n1}/{n2}")
        if not bad and i in cuts:
            bad = True
            if len(examples) < 5:
                examples.append(cuts[i])
        if not bad:
            open_poses.append(i)
        hits += bad
    # a part inside the next link across a joint (MuJoCo never collides the pair) fails a pose too;
    # tested exactly, only at the poses nothing else fails
    found = joint_overlaps(m, sorted(added), poses[open_poses]) if open_poses else {}
    overlaps = [replace(o, pose=open_poses[k]) for k, o in sorted(found.items())]
    for o in overlaps[: max(0, 5 - len(examples))]:
        examples.append(f"{o.geom1}/{o.geom2}")
    hits += len(overlaps)
    return (hits / counted if counted else 0.0), examples, overlaps


def _lowest_point(m: mujoco.MjModel, d: mujoco.MjData, geoms: np.ndarray) -> float:
    """Lowest world z of the selected geoms' oriented bounding boxes [m]."""
    ids = np.flatnonzero(geoms)
    centre, half = m.geom_aabb[ids, :3], m.geom_aabb[ids, 3:]
    rot = d.geom_xmat[ids].reshape(-1, 3, 3)
    z = d.geom_xpos[ids, 2] + np.einsum("nj,nj->n", rot[:, 2, :], centre)
    return float(np.min(z - np.einsum("nj,nj->n", np.abs(rot[:, 2, :]), half)))
