"""Interpenetration of bodies that MuJoCo's contact filter never compares: welded and parent/child pairs.

MuJoCo skips contacts between geoms of one rigid group (bodies welded together) and, unless the
parent is the world, between a body and its parent across a joint (``filterparent``). A part sunk
into the link it is welded to, or into the next link across a joint, therefore never shows up as a
contact. This module tests exactly those pairs, for every pair with a geom on one of the bodies
under audit (the bodies a submission adds or changes; pairs of stock geoms are the baseline and
are never reported):

1. broad phase: bounding spheres (``geom_rbound``) apart -> no overlap;
2. collision geometry: ``mj_geomDistance`` on the geoms (primitives exact, meshes as their convex
   hulls); a penetration no deeper than the pair's tolerance is accepted (the joint's fit);
3. exact material: the intersection volume of the two solids with manifold3d (primitives as meshes,
   ``geom_solid``); a hull overlap with no shared material (a part in a shell's concave side) is no
   overlap.

The reported depth is the collision-geometry penetration [m] (how far the part is sunk), the volume
the shared material [m^3]. Poses are joint positions ``qpos`` [rad]; welded pairs do not depend on
the pose and are tested at ``qpos0`` only.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.mjcf.geom_solid import geom_manifold, is_solid

__all__ = ["Overlap", "VOLUME_EPS", "find_overlaps", "skipped_pairs"]

VOLUME_EPS = 1e-10
"""Shared material below this is no overlap [m^3] (0.1 mm^3; manifold3d's round-off is ~1e-15)."""
_SEARCH_M = 0.01


@dataclass(frozen=True)
class Overlap:
    """Two parts occupying the same space.

    Attributes:
        geom1: The audited part (a geom of an added or changed body).
        body1: Its body.
        geom2: The part it sinks into.
        body2: That part's body.
        depth_m: Penetration of the collision geometry [m].
        volume_m3: Shared material [m^3].
        pose: Index of the pose in the audited poses; -1 for ``qpos0``.
        across_joint: True for a parent/child pair across a joint, False for a welded pair.
    """

    geom1: str
    body1: str
    geom2: str
    body2: str
    depth_m: float
    volume_m3: float
    pose: int
    across_joint: bool

    @property
    def message(self) -> str:
        how = "across their joint" if self.across_joint else "welded to it"
        where = "at the zero pose" if self.pose < 0 else f"at pose {self.pose}"
        return (
            f"part '{self.geom1}' of body '{self.body1}' is sunk {self.depth_m * 1e3:.1f} mm into "
            f"'{self.geom2}' of body '{self.body2}' ({how}; {self.volume_m3 * 1e9:.0f} mm^3 of shared "
            f"material) {where}"
        )


def _name(model: mujoco.MjModel, kind: mujoco.mjtObj, i: int) -> str:
    return mujoco.mj_id2name(model, kind, i) or f"{kind.name[6:].lower()}{i}"


def skipped_pairs(
    model: mujoco.MjModel, bodies: Iterable[int], fused: Iterable[int] = ()
) -> list[tuple[int, int, bool]]:
    """Geom pairs MuJoCo's contact filter skips with a geom on one of ``bodies``.

    Args:
        model: Compiled model.
        bodies: Ids of the audited bodies.
        fused: Ids of bodies whose welded pairs among themselves are one part (printed together):
            such pairs are not returned.

    Returns:
        ``(audited geom, other geom, across_joint)`` per pair, each unordered pair once.
    """
    audited, fused = set(int(b) for b in bodies), set(int(b) for b in fused)
    weld, parent = model.body_weldid, model.body_parentid
    by_weld: dict[int, list[int]] = {}
    for g in range(model.ngeom):
        if is_solid(model, g):
            by_weld.setdefault(int(weld[model.geom_bodyid[g]]), []).append(g)
    children: dict[int, list[int]] = {}
    for w in by_weld:
        if w != 0:
            children.setdefault(int(weld[parent[w]]), []).append(w)
    out: list[tuple[int, int, bool]] = []
    seen: set[tuple[int, int]] = set()
    for w1, geoms in sorted(by_weld.items()):
        up = int(weld[parent[w1]])
        near = [(w1, False)] + [(w, True) for w in children.get(w1, []) if w1 != 0]
        near += [(up, True)] if w1 != 0 and up != 0 else []
        for g1 in geoms:
            b1 = int(model.geom_bodyid[g1])
            if b1 not in audited:
                continue
            for w2, across in near:
                for g2 in by_weld.get(w2, []):
                    b2 = int(model.geom_bodyid[g2])
                    key = (min(g1, g2), max(g1, g2))
                    if b2 == b1 or key in seen or (not across and b1 in fused and b2 in fused):
                        continue
                    seen.add(key)
                    out.append((g1, g2, across))
    return sorted(out)


def _placed(man, xpos: np.ndarray, xmat: np.ndarray):
    mat = np.zeros((3, 4))
    mat[:, :3] = np.asarray(xmat).reshape(3, 3)
    mat[:, 3] = xpos
    return man.transform(mat)


def _relative(model, data, g: int, w: int) -> tuple[np.ndarray, np.ndarray]:
    """Pose of geom ``g`` in the frame of body ``w`` (position, 3 x 3 rotation)."""
    rw = data.xmat[w].reshape(3, 3)
    return rw.T @ (data.geom_xpos[g] - data.xpos[w]), rw.T @ data.geom_xmat[g].reshape(3, 3)


class _Solids:
    """Placed solids of one model at the current pose of ``data``, and each audited part less the
    baseline material of its own rigid group (the stock link it is fastened to), fixed in that
    group's frame."""

    def __init__(self, model, data, baseline: set[int], cache: dict) -> None:
        self.model, self.data, self.cache = model, data, cache
        self.baseline = baseline
        self._outside: dict[int, object] = {}

    def world(self, g: int):
        return _placed(
            geom_manifold(self.model, g, self.cache), self.data.geom_xpos[g], self.data.geom_xmat[g]
        )

    def group(self, w: int):
        """Union of the baseline geoms welded to body ``w`` (world frame, current pose), or None."""
        m = self.model
        geoms = [g for g in range(m.ngeom) if is_solid(m, g) and int(m.body_weldid[m.geom_bodyid[g]]) == w]
        parts = [self.world(g) for g in geoms if int(m.geom_bodyid[g]) in self.baseline]
        if not parts:
            return None
        import manifold3d

        return manifold3d.Manifold.batch_boolean(parts, manifold3d.OpType.Add)

    def outside(self, g: int):
        """Part ``g`` less its own group's baseline material, in the group's frame (at qpos0)."""
        if g not in self._outside:
            w = int(self.model.body_weldid[self.model.geom_bodyid[g]])
            pos, rot = _relative(self.model, self.data, g, w)
            part = _placed(geom_manifold(self.model, g, self.cache), pos, rot)
            base = self.group(w)
            if base is not None:
                rw = self.data.xmat[w].reshape(3, 3)
                inv = np.zeros((3, 4))
                inv[:, :3] = rw.T
                inv[:, 3] = -rw.T @ self.data.xpos[w]
                part = part - base.transform(inv)
            self._outside[g] = part
        return self._outside[g]


def _shared_volume(solids: _Solids, g1: int, g2: int, across: bool) -> float:
    """Material the pair shares beyond the baseline's own overlap [m^3]."""
    m, d = solids.model, solids.data
    if not across or not solids.baseline:
        return float((solids.world(g1) ^ solids.world(g2)).volume())
    w1, w2 = int(m.body_weldid[m.geom_bodyid[g1]]), int(m.body_weldid[m.geom_bodyid[g2]])
    if int(m.geom_bodyid[g2]) in solids.baseline:
        # (P n G) \ (S1 n S2) = (P \ S1) n G when G lies in S2
        part = _placed(solids.outside(g1), d.xpos[w1], d.xmat[w1])
        return float((part ^ solids.world(g2)).volume())
    shared = solids.world(g1) ^ solids.world(g2)
    s1, s2 = solids.group(w1), solids.group(w2)
    if s1 is not None and s2 is not None:
        shared = shared - (s1 ^ s2)
    return float(shared.volume())


def find_overlaps(
    model: mujoco.MjModel,
    bodies: Iterable[int],
    poses: np.ndarray | None = None,
    *,
    joint_tol: float,
    weld_tol: float,
    fused: Iterable[int] = (),
    baseline: Iterable[int] = (),
    volume_tol: float = VOLUME_EPS,
    weld_share: float = 0.0,
    first_per_pose: bool = False,
    cache: dict | None = None,
) -> list[Overlap]:
    """Overlaps of the audited bodies' geoms with the geoms MuJoCo's filter hides from them.

    Args:
        model: Compiled model.
        bodies: Ids of the audited bodies (added or changed by a submission).
        poses: Joint positions to test across-joint pairs at, shape (N, nq) [rad]; None: ``qpos0``.
        joint_tol: Largest collision-geometry penetration accepted across a joint [m].
        weld_tol: Largest penetration accepted between welded parts [m] (a part seated in a socket).
        fused: Bodies printed as one part with each other (``skipped_pairs``).
        baseline: Ids of the stock bodies: across a joint, the material their two rigid groups
            already share (the stock joint's own overlap) is not counted against a part.
        volume_tol: Shared material up to this is no overlap [m^3].
        weld_share: Welded pairs may also share up to this fraction of the smaller part's volume
            (a part seated in its host: a rod in a socket, a post through a wall) [1].
        first_per_pose: Stop at the first overlap of each pose (enough to fail the pose).
        cache: Per-geom manifold cache, reusable across calls on the same model.

    Returns:
        Every overlap beyond its tolerances, ordered by pose.
    """
    cache = {} if cache is None else cache
    pairs = skipped_pairs(model, bodies, fused)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    solids = _Solids(model, data, set(int(b) for b in baseline), cache)
    out: list[Overlap] = []
    obj_g, obj_b = mujoco.mjtObj.mjOBJ_GEOM, mujoco.mjtObj.mjOBJ_BODY

    def check(g1: int, g2: int, across: bool, pose: int) -> bool:
        tol = joint_tol if across else weld_tol
        gap = np.linalg.norm(data.geom_xpos[g1] - data.geom_xpos[g2])
        if gap > model.geom_rbound[g1] + model.geom_rbound[g2] - tol:
            return False
        dist = float(mujoco.mj_geomDistance(model, data, g1, g2, _SEARCH_M, None))
        if dist >= -tol:
            return False
        vol = _shared_volume(solids, g1, g2, across)
        allowed = volume_tol
        if not across and weld_share > 0:
            smaller = min(geom_manifold(model, g, cache).volume() for g in (g1, g2))
            allowed = max(volume_tol, weld_share * smaller)
        if vol <= allowed:
            return False
        b1, b2 = int(model.geom_bodyid[g1]), int(model.geom_bodyid[g2])
        out.append(
            Overlap(
                _name(model, obj_g, g1),
                _name(model, obj_b, b1),
                _name(model, obj_g, g2),
                _name(model, obj_b, b2),
                -dist,
                vol,
                pose,
                across,
            )
        )
        return True

    for g1, g2, across in pairs:
        if not across:
            check(g1, g2, False, -1)
    joint_pairs = [(g1, g2) for g1, g2, across in pairs if across]
    if joint_pairs and solids.baseline:
        for g1, _ in joint_pairs:
            solids.outside(g1)  # fixed in its group's frame: computed once, at qpos0
    qs = [None] if poses is None else list(np.asarray(poses, float))
    for i, q in enumerate(qs):
        if q is not None:
            data.qpos[:] = q
            mujoco.mj_kinematics(model, data)
        for k, (g1, g2) in enumerate(joint_pairs):
            if check(g1, g2, True, -1 if q is None else i) and first_per_pose:
                joint_pairs.insert(0, joint_pairs.pop(k))  # the pair that failed this pose first
                break
    return out
