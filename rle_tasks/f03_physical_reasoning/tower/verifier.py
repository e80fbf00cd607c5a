"""03-tower: twelve mixed pieces, the settled height of the tallest robot-free tower / H*.

Instance (from the secret): eleven boxes, long side a in [0.05, 0.11] m, short side 2b in
[0.042, 0.062] m (graspable across by the Panda gripper, 0.08 m stroke), thickness in [0.018, 0.035]
m, density 500 kg/m^3, lying on their largest face; and one wedge (a triangular prism, 0.08 x 0.06
x 0.04 m, ridge on top) that cannot support another piece. They spawn on twelve spots at the sides
of the table, shuffled by the secret.

Allowed resting orientations: the face a piece spawns on, any heading (what a top-down grasp keeps).
H* = ``optimum.optimal_tower`` (5 deg tipping margin at every interface). The measurement takes
the robot-free settled scene (``scene.settle``: the replayed velocities, ``SETTLE_S``, at rest = moved
under ``REST_DISP_M`` / ``REST_ANGLE`` over the last ``REST_WINDOW_S``) and reports the highest point
of any piece that is above the table top and at rest, minus the table top; score = height / H*,
clipped to [0, 1].
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.secrets import Secret, derive_rng
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from ..constants import TOWER_ID
from ..scene import CONFIG, Piece, settle
from ..session import settled_pieces
from .optimum import Block, TowerPlan, optimal_tower
from .scoring import RUBRIC

__all__ = ["BUILD_SPOT", "DENSITY", "Instance", "instance", "measure", "reference_plan", "verify"]

DENSITY = 500.0
"""Density of the pieces [kg/m^3]."""
WEDGE_HALF = (0.04, 0.03, 0.02)
"""Wedge bounding half extents [m] (ridge along x at the top)."""
BUILD_SPOT = (0.33, 0.0)
"""Where the shipped agent programs build (x, y) [m]."""
SPOTS = tuple((x, s * y) for x in (0.33, 0.2) for y in (0.25, 0.37, 0.49) for s in (-1, 1))
"""Twelve spawn spots (x, y) [m], all 0.35-0.62 m from the arm's base."""


@dataclass(frozen=True)
class Instance:
    """Pieces of one tower instance (``pieces``) and their optimum (``plan``, computed once)."""

    pieces: tuple[Piece, ...]

    def blocks(self) -> list[Block]:
        """The pieces as the optimiser sees them (resting on their spawn face)."""
        return [
            Block(p.name, min(p.half_size[:2]), 2 * p.half_size[2], p.mass, supports=p.shape == "box")
            for p in self.pieces
        ]

    @functools.cached_property
    def plan(self) -> TowerPlan:
        """The optimal tower (``optimum.optimal_tower``)."""
        return optimal_tower(self.blocks())

    @property
    def optimum(self) -> float:
        """H* [m]."""
        return self.plan.height


def instance(secret: Secret) -> Instance:
    """The instance of ``secret`` (the public key gives the development instance)."""
    rng = derive_rng(secret, TOWER_ID, "instance")
    spots = [SPOTS[i] for i in rng.permutation(len(SPOTS))]
    pieces = []
    for i in range(11):
        a, b, c = rng.uniform(0.05, 0.11), rng.uniform(0.042, 0.062), rng.uniform(0.018, 0.035)
        colour = (*rng.uniform(0.2, 0.95, 3), 1.0)
        x, y = spots[i]
        pieces.append(Piece(f"piece{i:02d}", (a / 2, b / 2, c / 2), (x, y, CONFIG.top_z + c / 2),
                            mass=DENSITY * a * b * c, rgba=colour))  # fmt: skip
    hx, hy, hz = WEDGE_HALF
    x, y = spots[11]
    pieces.append(Piece("wedge", WEDGE_HALF, (x, y, CONFIG.top_z + hz), mass=DENSITY * 4 * hx * hy * hz,
                        shape="wedge", rgba=(0.95, 0.95, 0.95, 1.0)))  # fmt: skip
    return Instance(tuple(pieces))


def reference_plan(inst: Instance) -> list[tuple[str, float]]:
    """Boxes of the optimal tower, bottom up, headings 0 (the shipped agent leaves the wedge out)."""
    return [(name, 0.0) for name in inst.plan.order if name != "wedge"]


def _top(pose: np.ndarray, half: tuple[float, float, float]) -> float:
    w, x, y, z = pose[3:7]
    row = np.array([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)])  # R[2, :]
    return float(pose[2] + np.abs(row) @ np.asarray(half))


def measure(
    inst: Instance, poses: dict[str, np.ndarray], velocities: dict[str, np.ndarray] | None = None
) -> dict[str, float]:
    """Settle ``poses`` (with ``velocities``, the replayed state's, when given) without the robot
    (``scene.settle``); height of the highest piece above the table top that is at rest."""
    settled = settle(inst.pieces, poses, velocities=velocities)
    height, on_table = 0.0, 0
    for piece in inst.pieces:
        pose = settled.poses[piece.name]
        if pose[2] > CONFIG.top_z and settled.at_rest[piece.name]:
            on_table += 1
            height = max(height, _top(pose, piece.half_size) - CONFIG.top_z)
    return {
        "height_m": height,
        "optimum_m": inst.optimum,
        "ratio": height / inst.optimum,
        "pieces_on_table": on_table,
        "max_window_disp_m": settled.max_disp_m,
    }


def verify(root: Path, ctx: VerifyContext) -> VerifierReport:
    """Ledger gate, replay, robot-free settle, tower height / H*."""
    findings = Findings()
    s = settled_pieces(root, ctx, TOWER_ID, instance, RUBRIC, "height", findings)
    if isinstance(s, VerifierReport):
        return s
    inst, gate, privileged = s.instance, s.gate, s.privileged
    m = measure(inst, gate.poses, gate.velocities)
    message = f"tower {1000 * m['height_m']:.1f} mm of H* = {1000 * m['optimum_m']:.1f} mm"
    outcome = Outcome({"scene": RUBRIC.spec("height").score(m["ratio"])}, message, m)
    return RUBRIC.report(
        {"height": outcome}, valid=True, errors=findings.errors,
        native_metrics={"steps": gate.steps, "optimal_order": list(inst.plan.order), "attempt": gate.attempt,
                        "privileged_session": privileged},
    )  # fmt: skip
