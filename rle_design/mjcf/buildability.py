"""Build-ability audit: every part of a rigid body is joined to the rest of it, and every child body
meets its parent.

A part is a geom. Within one body, geoms whose surfaces come within ``tol`` of each other (touching
or overlapping, measured with MuJoCo's ``mj_geomDistance`` on the geoms themselves, not on bounding
boxes) form one assembly; a body whose geoms fall into several assemblies has parts hanging in the
air, and each detached assembly is reported with its gap to the largest one. A child body's geoms must
come within its tolerance of its parent's geoms (a bracket, a bolt face, an axle). Meshes are measured
on their convex hulls (MuJoCo's collision geometry), so a gap inside a concave part can be missed.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import mujoco

__all__ = ["Detached", "audit_buildability", "geom_gap"]

_SEARCH_M = 1.0  # distances beyond this are reported as this [m]


@dataclass(frozen=True)
class Detached:
    """A part, or a body, not joined to the structure it belongs to.

    Attributes:
        body: The body whose part is detached, or the child body that does not meet its parent.
        part: The first geom of the detached assembly (``kind == "part"``) or of the child body.
        other: The nearest geom of the structure it should be joined to.
        gap_m: Surface distance between the two [m] (capped at 1 m).
        kind: ``"part"`` (inside a body) or ``"body"`` (a child body and its parent).
    """

    body: str
    part: str
    other: str
    gap_m: float
    kind: str

    @property
    def message(self) -> str:
        where = f"in body '{self.body}'" if self.kind == "part" else f"of body '{self.body}' to its parent"
        return (
            f"part '{self.part}' {where} is not fastened: {self.gap_m * 1e3:.1f} mm from the nearest "
            f"structure ('{self.other}')"
        )


def geom_gap(model: mujoco.MjModel, data: mujoco.MjData, g1: int, g2: int) -> float:
    """Surface distance between two geoms at the current pose [m]; negative when they overlap."""
    return float(mujoco.mj_geomDistance(model, data, g1, g2, _SEARCH_M, None))


def _name(model: mujoco.MjModel, kind: mujoco.mjtObj, i: int) -> str:
    return mujoco.mj_id2name(model, kind, i) or f"{kind.name[6:].lower()}{i}"


def _components(model: mujoco.MjModel, data: mujoco.MjData, geoms: list[int], tol: float) -> list[list[int]]:
    parent = list(range(len(geoms)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i in range(len(geoms)):
        for j in range(i + 1, len(geoms)):
            if root(i) != root(j) and geom_gap(model, data, geoms[i], geoms[j]) <= tol:
                parent[root(i)] = root(j)
    groups: dict[int, list[int]] = {}
    for i, g in enumerate(geoms):
        groups.setdefault(root(i), []).append(g)
    return sorted(groups.values(), key=lambda c: (-len(c), c[0]))


def _nearest(model, data, a: list[int], b: list[int]) -> tuple[float, int, int]:
    return min((geom_gap(model, data, i, j), i, j) for i in a for j in b)


def audit_buildability(
    model: mujoco.MjModel,
    *,
    tol: float = 1e-3,
    bodies: Iterable[str] | None = None,
    parent_tol: Mapping[str, float] | None = None,
) -> list[Detached]:
    """Parts not joined to their body's structure and child bodies not meeting their parents.

    The model is measured at ``qpos0``. Planes and height fields (the ground) are not parts.

    Args:
        model: Compiled model.
        tol: Largest surface gap that still counts as joined [m].
        bodies: Names of the bodies to audit (default: every body but the world).
        parent_tol: Per child body, a larger gap allowed to its parent [m] (e.g. a hub motor that
            spans the clearance between a wheel and the frame).

    Returns:
        One ``Detached`` per detached assembly and per child body that does not meet its parent.
    """
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    parent_tol = dict(parent_tol or {})
    skip = {int(mujoco.mjtGeom.mjGEOM_PLANE), int(mujoco.mjtGeom.mjGEOM_HFIELD)}
    parts: dict[int, list[int]] = {}
    for g in range(model.ngeom):
        if int(model.geom_type[g]) not in skip:
            parts.setdefault(int(model.geom_bodyid[g]), []).append(g)
    wanted = None if bodies is None else set(bodies)
    out: list[Detached] = []
    obj_g, obj_b = mujoco.mjtObj.mjOBJ_GEOM, mujoco.mjtObj.mjOBJ_BODY
    for b in range(1, model.nbody):
        name = _name(model, obj_b, b)
        if wanted is not None and name not in wanted or b not in parts:
            continue
        comps = _components(model, data, parts[b], tol)
        for comp in comps[1:]:
            gap, i, j = _nearest(model, data, comp, comps[0])
            out.append(Detached(name, _name(model, obj_g, i), _name(model, obj_g, j), gap, "part"))
        p = int(model.body_parentid[b])
        if p == 0 or p not in parts:
            continue
        gap, i, j = _nearest(model, data, parts[b], parts[p])
        if gap > parent_tol.get(name, tol):
            out.append(Detached(name, _name(model, obj_g, i), _name(model, obj_g, j), gap, "body"))
    return out
