"""Ground-contact forces of a MuJoCo model: per-wheel normal forces, contact points, centre of pressure.

Normal forces come from ``mujoco.mj_contactForce`` (first component of the contact-frame wrench). A
contact belongs to a support (wheel, foot) when either of its geoms is one of that support's geoms.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.errors import MissingElement

__all__ = ["ContactSample", "SupportSet", "centre_of_pressure", "sample_contacts"]


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
        all_names = [model.geom(i).name for i in range(model.ngeom)]

        def gid(name: str) -> int:
            i = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name)
            if i < 0:
                raise MissingElement("geom", name, available=all_names, code="contract.missing_geom")
            return i

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


def sample_contacts(model: mujoco.MjModel, data: mujoco.MjData, supports: SupportSet) -> ContactSample:
    """Normal force and contact point of each support from ``data.contact`` (after mj_step/mj_forward)."""
    k = len(supports.names)
    owner = {g: i for i, gs in enumerate(supports.geom_ids) for g in gs}
    ground = set(supports.ground_ids)
    normal = np.zeros(k)
    moment = np.zeros((k, 3))
    wrench = np.zeros(6)
    for c in range(data.ncon):
        con = data.contact[c]
        g1, g2 = int(con.geom1), int(con.geom2)
        if g1 in ground:
            g1, g2 = g2, g1
        if g2 not in ground or g1 not in owner or con.efc_address < 0:
            continue
        mujoco.mj_contactForce(model, data, c, wrench)
        fn = max(0.0, float(wrench[0]))
        i = owner[g1]
        normal[i] += fn
        moment[i] += fn * np.asarray(con.pos)
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
