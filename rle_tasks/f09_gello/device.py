"""The leader device: the stock leader of each robot as shipped, and its hidden copies.

``stock_model`` / ``stock_names`` give the stock assembly (``assets/<robot>/lead.xml``) a submission
is checked against (``stock_contract``, ``submission``); ``device_variations`` draws the verifier's
hidden device copies (stock link masses and inertias scaled, a point payload at the handle), and
``battery_model`` a copy with the verifier's physics (dt 2 ms, noslip, no contacts).
"""

from __future__ import annotations

import functools
from pathlib import Path

import mujoco
import numpy as np

from rle_design.catalog import load_catalog
from rle_design.scene import MassScale, PointMass, Uniform, Variation, VariationSpace
from rle_tasks.f09_gello.assembly import HANDLE_SITE

ASSET_DIR = Path(__file__).resolve().parent / "assets"
STEEL_DENSITY = float(load_catalog("materials").get("steel").density)
"""Nominal steel [kg/m^3] (materials catalog), what the reference's counterweights are made of."""
OBJ = mujoco.mjtObj


@functools.cache
def stock_model(robot: str) -> mujoco.MjModel:
    """Compiled stock leader of ``robot`` (shipped assets)."""
    return mujoco.MjModel.from_xml_path(str(ASSET_DIR / robot / "lead.xml"))


def stock_names(robot: str) -> tuple[list[str], list[str], list[str]]:
    """Stock body, joint and geom names."""
    m = stock_model(robot)
    bodies = [mujoco.mj_id2name(m, OBJ.mjOBJ_BODY, b) for b in range(1, m.nbody)]
    joints = [mujoco.mj_id2name(m, OBJ.mjOBJ_JOINT, j) for j in range(m.njnt)]
    geoms = [mujoco.mj_id2name(m, OBJ.mjOBJ_GEOM, g) for g in range(m.ngeom)]
    return bodies, joints, geoms


def battery_model(m: mujoco.MjModel) -> mujoco.MjModel:
    """Copy with the verifier's physics: dt 2 ms, noslip 10 (frictionloss sticks), no contacts."""
    b = mujoco.MjModel.from_xml_string("<mujoco/>") if m is None else _copy(m)
    b.opt.timestep = 0.002
    b.opt.noslip_iterations = 10
    b.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    return b


def _copy(m: mujoco.MjModel) -> mujoco.MjModel:
    import copy

    return copy.deepcopy(m)


def device_variations(
    dof: int, spread: float = 0.15, payload: tuple[float, float] = (0.01, 0.04)
) -> VariationSpace:
    """Hidden device copies: stock link masses (and inertias) uniformly within +-``spread``, and a point
    payload uniform in ``payload`` [kg] merged into the handle's body at the handle site."""
    links = tuple(f"link{k + 1}" for k in range(dof))
    return VariationSpace(
        (
            MassScale("link_scale", Uniform(1 - spread, 1 + spread, "1"), bodies=links),
            PointMass("payload", Uniform(*payload, "kg"), site=HANDLE_SITE),
        )
    )


def draw_variation(rng: np.random.Generator, dof: int) -> Variation:
    """One hidden device copy of a leader with ``dof`` joints."""
    return device_variations(dof).sample(rng)


def apply_variation(m: mujoco.MjModel, var: Variation) -> mujoco.MjModel:
    """Copy of ``m`` with the variation applied."""
    return var.apply(m)
