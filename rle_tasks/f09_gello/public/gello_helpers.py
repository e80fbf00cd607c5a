"""Public analysis helpers of 09-gello (copied into the agent's workspace as ``gello_helpers.py``).

Nominal dynamics of a leader file: Pinocchio model, springs, residual torque maps over workspace grids,
the holding-torque probe model, and the home poses. Everything here is public: the hidden device
copies differ from the nominal leader only by link-mass factors and a handle payload.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from rle_design.kinematics import (
    GravityMap,
    KinematicModel,
    model_from_mujoco,
    spring_torque,
    springs_from_mujoco,
)
from rle_design.mjcf.material_mass import InertialTolerance
from rle_design.mjcf.workshop import WorkshopRules, workshop_findings
from rle_design.scene import arm_ids, robot_constants

HOME: dict[str, tuple[float, ...]] = {robot: robot_constants(robot).home for robot in arm_ids()}
"""Home pose of each leader [rad], its follower's ``home`` keyframe (a leader mirrors its follower joint
for joint): the first of the 16 probes is always measured here."""
GRID_SEED = 20261122
PUBLIC_GRID_SIZE = 256
"""Poses of the public workspace grid on which the verifier checks spring paths (``contract.spring_path``)."""
LIMIT_MARGIN = 0.1
"""Test and grid poses stay this far inside the joint limits [rad]."""
PROBE_FRICTION_BAND = 0.5
"""Probe torque error: uniform within +-PROBE_FRICTION_BAND x the joint frictionloss (static friction)."""
PROBE_NOISE = 0.002
"""... plus Gaussian current-sensing noise of this standard deviation [N m]."""


WORKSHOP = WorkshopRules(
    joint_tol=1e-4,
    weld_tol=1e-4,
    shared_volume=1e-9,
    weld_share=0.25,
    inertial=InertialTolerance(mass_rtol=1e-3, com_tol=1e-3, inertia_rtol=0.01),
    materials=(),
    massless_ok=False,
    dynamic_factor=2.0,
    safety_factor={"pla": 2.0, "petg": 2.0, "aluminium_6063": 1.5, "steel": 1.5},
    deflection_ratio=0.02,
    join_tol=1e-3,
)
"""The verifier's workshop rules for added parts (README, "Thresholds"): across a joint a part may
penetrate the next link's collision geometry 0.1 mm and share 1 mm^3 of material beyond what the
stock joint shares; a part may share a quarter of its volume with a part welded to it (a seat); every part is a catalog
material within its density range (all materials of ``materials.yaml``), massless parts are not
allowed; inertials within 0.1 % (mass), 1 mm (centre of mass), 1 % (inertia) of the geometry;
beams hold 2 x their weight plus the springs' worst tension at half (printed) or 1/1.5 (metal) of
the yield strength and sag at most 2 % of their span."""


def workshop_check(lead_xml: str | Path, robot: str, stock_xml: str | Path | None = None) -> list[str]:
    """Run the verifier's workshop rules on a leader before submitting it (public helper).

    Checks the bodies ``lead_xml`` adds to the stock leader: material densities and inertials, parts
    seated in parts welded to them, beam strength and sag (spring tensions at their worst pose of
    the public grid), and parts inside the next link across a joint at each public-grid pose (the
    verifier counts each such pose of its hidden grid as a motion-clearance failure).

    Args:
        lead_xml: The leader file.
        robot: ``"panda"``, ``"ur5e"`` or ``"xarm7"``.
        stock_xml: The stock leader (default: ``leaders/<robot>/lead.xml`` beside this module, else
            the bodies named ``base``/``link<k>`` are taken as stock).

    Returns:
        One ``"code: message"`` line per finding (the across-joint poses summed up in one line);
        empty when the leader passes.
    """
    lead_xml = Path(lead_xml)
    spec = mujoco.MjSpec.from_file(str(lead_xml))
    m = spec.compile()
    stock_names: set[str] | None = None
    candidate = Path(stock_xml) if stock_xml else Path(__file__).parent / "leaders" / robot / "lead.xml"
    if candidate.is_file():
        s = mujoco.MjModel.from_xml_path(str(candidate))
        stock_names = {mujoco.mj_id2name(s, mujoco.mjtObj.mjOBJ_BODY, b) for b in range(1, s.nbody)}
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) or "" for b in range(m.nbody)]
    if stock_names is None:
        stock_names = {n for n in names if n == "base" or (n.startswith("link") and n[4:].isdigit())}
    added = [b for b in range(1, m.nbody) if names[b] not in stock_names]
    stock = [b for b in range(1, m.nbody) if b not in set(added)]
    grid = workspace_grid(m.jnt_range, PUBLIC_GRID_SIZE)
    found = workshop_findings(spec, m, added, WORKSHOP, poses=grid, baseline=stock, fused=added)
    out = [f"{f.code}: {f.message}" for f in found if f.code != "interpenetration.joint"]
    poses = [f.message for f in found if f.code == "interpenetration.joint"]
    if poses:  # one line for all the public-grid poses where a part lies inside the next link
        out.append(
            f"interpenetration.joint: at {len(poses)} of {len(grid)} public-grid poses an added part lies "
            f"inside the next link across a joint (each such pose fails motion clearance); first: {poses[0]}"
        )
    return out


def workspace_grid(ranges: np.ndarray, n: int, seed: int = GRID_SEED) -> np.ndarray:
    """``n`` poses uniformly inside the joint ranges (less ``LIMIT_MARGIN``), shape (n, dof) [rad]."""
    ranges = np.asarray(ranges, float)
    rng = np.random.default_rng(seed)
    return rng.uniform(ranges[:, 0] + LIMIT_MARGIN, ranges[:, 1] - LIMIT_MARGIN, size=(n, len(ranges)))


def load_leader(path: str | Path) -> tuple[mujoco.MjModel, KinematicModel, list]:
    """Compiled model, Pinocchio model and springs of a (trusted) ``lead.xml``."""
    m = mujoco.MjModel.from_xml_path(str(path))
    km = model_from_mujoco(m)
    return m, km, springs_from_mujoco(m, km)


def residual(km: KinematicModel, springs: list, poses: np.ndarray) -> np.ndarray:
    """Holding torque the servos must supply, r(q) = g(q) - tau_spring(q), shape (N, dof) [N m]."""
    poses = np.atleast_2d(poses)
    r = GravityMap(km)(poses)
    if springs:
        r -= np.array([spring_torque(km, springs, q) for q in poses])
    return r


def peak_torque(km: KinematicModel, springs: list, ranges: np.ndarray, n: int = 4096) -> np.ndarray:
    """Per-joint peak |r| over a workspace grid [N m] (compare with the 0.35 N m servo limit)."""
    return np.abs(residual(km, springs, workspace_grid(ranges, n))).max(axis=0)
