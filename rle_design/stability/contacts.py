"""Ground-contact forces of a MuJoCo model: per-wheel normal forces, contact points, centre of pressure.

Normal forces come from ``mujoco.mj_contactForce`` (first component of the contact-frame wrench). A
contact belongs to a support (wheel, foot) when either of its geoms is one of that support's geoms.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.scene.elements import element_id

__all__ = ["ContactSample", "SupportSet", "centre_of_pressure", "sample_contacts", "support_normals"]


@dataclass(frozen=True)
class SupportSet:
    """The geoms through which a machine stands on the ground.

    Attributes:
        names: Support names, e.g. ``("wheel_fl", ...)``.
        geom_ids: One tuple of geom ids per support.
        ground_ids: Geom ids of the ground (contacts with anything else are ignored).
    """

    names: tuple[str, ...]
    geom_ids: tuple[tuple[int, ...], ...]
    ground_ids: tuple[int, ...]

    @classmethod
    def from_names(
        cls, model: mujoco.MjModel, supports: dict[str, Sequence[str]], ground: Sequence[str] = ("floor",)
    ) -> SupportSet:
        """Build from geom names; raises ``MissingElement`` naming the available geoms."""

        def gid(name: str) -> int:
            return element_id(model, "geom", name, code="contract.missing_geom")

        names = tuple(supports)
        return cls(
            names, tuple(tuple(gid(g) for g in supports[n]) for n in names), tuple(gid(g) for g in ground)
        )


@dataclass(frozen=True)
class ContactSample:
    """Ground contacts of each support at one instant.

    Attributes:
        normal: Normal force per support [N] (sum over its contacts).
        points: Force-weighted contact point per support (NaN where no contact) [m].
        cop: Centre of pressure of all supports (x, y) [m] (NaN without load).
    """

    normal: np.ndarray
    points: np.ndarray
    cop: np.ndarray


@functools.lru_cache(maxsize=64)
def _owner_table(ngeom: int, supports: SupportSet) -> tuple[np.ndarray, np.ndarray]:
    """Support index of every geom (-1: none) and the ground mask, for a model of ``ngeom`` geoms."""
    owner = np.full(ngeom, -1, dtype=int)
    for i, gs in enumerate(supports.geom_ids):
        owner[list(gs)] = i
    ground = np.zeros(ngeom, dtype=bool)
    ground[list(supports.ground_ids)] = True
    return owner, ground


def _support_forces(
    model: mujoco.MjModel, data: mujoco.MjData, supports: SupportSet
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Normal force [N] of each support-ground contact, its support index and its contact index.

    Vectorised over contacts: with elliptic cones the normal force is the first row of each contact's
    constraint block (``efc_force[efc_address]``), which is what ``mj_contactForce`` returns; with
    pyramidal cones ``mj_contactForce`` is called per contact.
    """
    owner, ground = _owner_table(model.ngeom, supports)
    n = data.ncon
    if not n:
        return np.zeros(0), np.zeros(0, dtype=int), np.zeros(0, dtype=int)
    con = data.contact
    g1, g2 = con.geom1[:n], con.geom2[:n]
    adr = con.efc_address[:n]
    swap = ground[g1]
    body_g = np.where(swap, g2, g1)
    other = np.where(swap, g1, g2)
    idx = np.nonzero(ground[other] & (owner[body_g] >= 0) & (adr >= 0))[0]
    if model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC:
        fn = data.efc_force[adr[idx]]
    else:
        wrench = np.zeros(6)
        fn = np.empty(idx.size)
        for j, c in enumerate(idx):
            mujoco.mj_contactForce(model, data, int(c), wrench)
            fn[j] = wrench[0]
    return np.maximum(fn, 0.0), owner[body_g[idx]], idx


@functools.lru_cache(maxsize=64)
def _owner_lists(ngeom: int, supports: SupportSet) -> tuple[list[int], list[bool]]:
    """``_owner_table`` as Python lists, for the per-contact loop of ``support_normals``."""
    owner, ground = _owner_table(ngeom, supports)
    return owner.tolist(), ground.tolist()


def support_normals(model: mujoco.MjModel, data: mujoco.MjData, supports: SupportSet) -> np.ndarray:
    """Normal force of each support [N] (the ``normal`` of ``sample_contacts``, without points)."""
    return np.array(support_normal_list(model, data, supports))


def support_normal_list(model: mujoco.MjModel, data: mujoco.MjData, supports: SupportSet) -> list[float]:
    """``support_normals`` as a list of floats.

    Sampled every few physics steps in long episodes: with elliptic cones and a few contacts a plain
    loop beats the vectorised path; both add each support's forces in contact order (same sums).
    """
    n = data.ncon
    if n > 64 or model.opt.cone != mujoco.mjtCone.mjCONE_ELLIPTIC:
        normal = np.zeros(len(supports.names))
        fn, who, _ = _support_forces(model, data, supports)
        np.add.at(normal, who, fn)
        return normal.tolist()
    owner, ground = _owner_lists(model.ngeom, supports)
    normal = [0.0] * len(supports.names)
    if n:
        con = data.contact
        rows, who = [], []
        for g1, g2, adr in zip(con.geom1[:n].tolist(), con.geom2[:n].tolist(), con.efc_address[:n].tolist()):
            body, other = (g2, g1) if ground[g1] else (g1, g2)
            if ground[other] and owner[body] >= 0 and adr >= 0:
                rows.append(adr)
                who.append(owner[body])
        if rows:
            for i, f in zip(who, data.efc_force[rows].tolist()):
                normal[i] += 0.0 if f < 0.0 else f  # np.maximum(f, 0.0): NaN and -0.0 kept
    return normal


def sample_contacts(model: mujoco.MjModel, data: mujoco.MjData, supports: SupportSet) -> ContactSample:
    """Normal force and contact point of each support from ``data.contact`` (after mj_step/mj_forward)."""
    k = len(supports.names)
    normal = np.zeros(k)
    moment = np.zeros((k, 3))
    fn, who, idx = _support_forces(model, data, supports)
    if idx.size:
        np.add.at(normal, who, fn)
        np.add.at(moment, who, fn[:, None] * data.contact.pos[: data.ncon][idx])
    points = np.full((k, 3), np.nan)
    loaded = normal > 0
    points[loaded] = moment[loaded] / normal[loaded, None]
    return ContactSample(normal, points, centre_of_pressure(points, normal))


def centre_of_pressure(points: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Normal-force-weighted mean of contact points (x, y) [m]; NaN when nothing is loaded."""
    normal = np.asarray(normal, dtype=float)
    total = float(normal.sum())
    if total <= 0:
        return np.full(2, np.nan)
    pts = np.nan_to_num(np.asarray(points, dtype=float)[:, :2])
    return (normal[:, None] * pts).sum(axis=0) / total
