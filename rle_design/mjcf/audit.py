"""Mass, inertia and extent audit of a compiled model at its reference configuration ``qpos0``.

Bounding box: every geom except planes, in world coordinates after ``mj_forward`` at ``qpos0``; mesh
geoms use their vertices (exact), other geoms the world box around their oriented local AABB
(``geom_aabb``; exact for boxes and spheres, tight for capsules/cylinders/ellipsoids).

Footprint: the x/y extent of the *lowest contact geoms*: collision geoms (``contype`` or
``conaffinity`` non-zero) of non-world bodies whose lowest point lies within ``contact_tol`` of the
lowest such point, i.e. what would touch a floor (the wheels of a base, the feet of a stand). When the
model has no such geom the footprint is the x/y extent of the whole bounding box
(``footprint_source == "model"``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.errors import MissingElement

__all__ = ["BodyAudit", "ModelAudit", "audit_model"]

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class BodyAudit:
    """Mass properties of one body.

    Attributes:
        name: Body name (``body<i>`` when unnamed).
        mass: Body mass [kg].
        inertia: Principal moments of inertia about the body COM [kg m^2].
        inertia_valid: Moments positive and satisfying the triangle inequality (A + B >= C).
        reason: Why the inertia is invalid ("" when valid).
    """

    name: str
    mass: float
    inertia: Vec3
    inertia_valid: bool
    reason: str


@dataclass(frozen=True)
class ModelAudit:
    """Audit of a compiled model at ``qpos0``.

    Attributes:
        total_mass: Sum of body masses [kg].
        com: Whole-model centre of mass in world coordinates [m].
        bodies: Per-body audit, world body excluded, in body id order.
        bbox_min: Lower corner of the world bounding box of all non-plane geoms [m].
        bbox_max: Upper corner [m].
        footprint: (x extent, y extent) of the footprint rectangle [m].
        footprint_min: Lower x/y corner of the footprint [m].
        footprint_max: Upper x/y corner of the footprint [m].
        footprint_source: ``"contact"`` (lowest contact geoms) or ``"model"`` (whole bounding box).
        counts: Element counts (nbody excludes the world body).
    """

    total_mass: float
    com: Vec3
    bodies: tuple[BodyAudit, ...]
    bbox_min: Vec3
    bbox_max: Vec3
    footprint: tuple[float, float]
    footprint_min: tuple[float, float]
    footprint_max: tuple[float, float]
    footprint_source: str
    counts: Mapping[str, int]

    @property
    def size(self) -> Vec3:
        """Bounding-box size (x, y, z) [m]."""
        return tuple(float(b - a) for a, b in zip(self.bbox_min, self.bbox_max))

    @property
    def invalid_inertia(self) -> tuple[BodyAudit, ...]:
        return tuple(b for b in self.bodies if not b.inertia_valid)

    def body(self, name: str) -> BodyAudit:
        """Audit of body ``name``; ``MissingElement`` lists the bodies."""
        for b in self.bodies:
            if b.name == name:
                return b
        raise MissingElement("body", name, available=[b.name for b in self.bodies])


def _inertia_reason(moments: np.ndarray, mass: float) -> str:
    if mass <= 0 and not moments.any():
        return "zero mass and inertia"
    if (moments <= 0).any():
        return f"non-positive principal moment in {np.round(moments, 12).tolist()}"
    a, b, c = np.sort(moments)
    if a + b < c * (1 - 1e-9):
        return f"triangle inequality violated: {a:.6g} + {b:.6g} < {c:.6g}"
    return ""


def _geom_world_points(model: mujoco.MjModel, data: mujoco.MjData, g: int) -> np.ndarray:
    xpos, xmat = data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3)
    if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH and model.geom_dataid[g] >= 0:
        m = model.geom_dataid[g]
        adr, num = model.mesh_vertadr[m], model.mesh_vertnum[m]
        local = model.mesh_vert[adr : adr + num]
    else:
        center, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
        local = center + signs * half
    return xpos + local @ xmat.T


def audit_model(model: mujoco.MjModel, contact_tol: float = 0.005) -> ModelAudit:
    """Audit ``model`` at ``qpos0`` (a fresh ``MjData`` and ``mj_forward``).

    Args:
        model: Compiled model.
        contact_tol: Height band above the lowest contact point that counts as touching [m].
    """
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    bodies = []
    for i in range(1, model.nbody):
        moments = np.asarray(model.body_inertia[i], dtype=float)
        mass = float(model.body_mass[i])
        reason = _inertia_reason(moments, mass)
        name = model.body(i).name or f"body{i}"
        bodies.append(BodyAudit(name, mass, tuple(map(float, moments)), not reason, reason))

    boxes, contact = [], []
    for g in range(model.ngeom):
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE:
            continue
        pts = _geom_world_points(model, data, g)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        boxes.append((lo, hi))
        if model.geom_bodyid[g] != 0 and (model.geom_contype[g] or model.geom_conaffinity[g]):
            contact.append((lo, hi))
    if boxes:
        bmin = np.min([b[0] for b in boxes], axis=0)
        bmax = np.max([b[1] for b in boxes], axis=0)
    else:
        bmin = bmax = np.zeros(3)
    if contact:
        zlow = min(lo[2] for lo, _ in contact)
        touching = [(lo, hi) for lo, hi in contact if lo[2] <= zlow + contact_tol]
        fmin = np.min([t[0][:2] for t in touching], axis=0)
        fmax = np.max([t[1][:2] for t in touching], axis=0)
        source = "contact"
    else:
        fmin, fmax, source = bmin[:2], bmax[:2], "model"

    counts = {
        "nbody": model.nbody - 1,
        "njnt": model.njnt,
        "nq": model.nq,
        "nv": model.nv,
        "ngeom": model.ngeom,
        "nsite": model.nsite,
        "nmesh": model.nmesh,
        "nu": model.nu,
        "neq": model.neq,
        "ntendon": model.ntendon,
        "nsensor": model.nsensor,
    }
    f2 = lambda v: (float(v[0]), float(v[1]))  # noqa: E731
    return ModelAudit(
        total_mass=float(np.sum(model.body_mass)),
        com=tuple(map(float, data.subtree_com[0])),
        bodies=tuple(bodies),
        bbox_min=tuple(map(float, bmin)),
        bbox_max=tuple(map(float, bmax)),
        footprint=f2(np.asarray(fmax) - np.asarray(fmin)),
        footprint_min=f2(fmin),
        footprint_max=f2(fmax),
        footprint_source=source,
        counts=counts,
    )
