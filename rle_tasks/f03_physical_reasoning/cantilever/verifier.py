"""03-cantilever: four identical blocks, the settled overhang beyond the table edge.

Instance (from the secret): block length L in [0.14, 0.18] m, cross-section 0.04 m (y) x 0.03 m (z),
spruce-like density 450 kg/m^3; the four blocks lie on the table, long axis along x (the edge
normal), at four secret-jittered spots.

Measurement (after the robot-free settle, ``scene.settle``, from the replayed poses and velocities): a
block counts when its centre is above the table top and it is at rest (moved under ``REST_DISP_M`` and
``REST_ANGLE`` over the last ``REST_WINDOW_S`` of ``SETTLE_S``); its reach along the edge normal is
``x_c + (L/2)|u_x|`` with ``u`` its long axis, so turning a block in yaw never lengthens it (the 3-D
diagonal trick cannot beat the 2-D optimum); the overhang is the largest reach minus ``edge_x``, and
the score is ``overhang / ((15 - 4 sqrt 2)/8 L)`` clipped to [0, 1].
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.secrets import Secret, derive_rng
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from ..constants import CANTILEVER_ID
from ..scene import CONFIG, Piece, settle
from ..session import settled_pieces
from .scoring import PZ4, RUBRIC

__all__ = ["DENSITY", "Instance", "instance", "measure", "verify"]

DENSITY = 450.0
"""Block density [kg/m^3]."""
WIDTH = 0.04
HEIGHT = 0.03


@dataclass(frozen=True)
class Instance:
    """One cantilever instance.

    Attributes:
        length: Block length L [m].
        pieces: The four blocks, as spawned.
    """

    length: float
    pieces: tuple[Piece, ...]

    @classmethod
    def build(cls, length: float, spots: np.ndarray) -> Instance:
        """Four blocks of length ``length`` [m] lying at ``spots`` ((x, y) [m]), long axis along x."""
        mass = DENSITY * length * WIDTH * HEIGHT
        colours = ((0.85, 0.3, 0.2, 1), (0.2, 0.6, 0.85, 1), (0.3, 0.75, 0.3, 1), (0.9, 0.75, 0.2, 1))
        pieces = tuple(
            Piece(
                f"block{i}",
                (length / 2, WIDTH / 2, HEIGHT / 2),
                (float(x), float(y), CONFIG.top_z + HEIGHT / 2),
                mass=mass,
                rgba=colours[i],
            )  # fmt: skip
            for i, (x, y) in enumerate(spots)
        )
        return cls(float(length), pieces)

    @property
    def optimum(self) -> float:
        """Paterson-Zwick overhang of four blocks [m]."""
        return PZ4 * self.length


def instance(secret: Secret) -> Instance:
    """The instance of ``secret`` (the public key gives the development instance)."""
    rng = derive_rng(secret, CANTILEVER_ID, "instance")
    length = float(rng.uniform(0.14, 0.18))
    ys = np.array([-0.33, -0.2, 0.2, 0.33]) + rng.uniform(-0.01, 0.01, 4)
    xs = 0.3 + rng.uniform(-0.03, 0.03, 4)
    return Instance.build(length, np.column_stack([xs, ys]))


def reach(pose: np.ndarray, length: float) -> float:
    """x of the block's far end along the edge normal: x_c + (L/2)|u_x| [m]."""
    w, x, y, z = pose[3:7]
    u_x = 1.0 - 2.0 * (y * y + z * z)  # first column of the rotation matrix, x component
    return float(pose[0] + 0.5 * length * abs(u_x))


def measure(
    inst: Instance, poses: dict[str, np.ndarray], velocities: dict[str, np.ndarray] | None = None
) -> dict[str, float]:
    """Settle ``poses`` (with ``velocities``, the replayed state's, when given) without the robot and
    measure the overhang (see the module docstring)."""
    settled = settle(inst.pieces, poses, velocities=velocities)
    reaches, standing = [], 0
    for piece in inst.pieces:
        pose = settled.poses[piece.name]
        if pose[2] > CONFIG.top_z and settled.at_rest[piece.name]:
            standing += 1
            reaches.append(reach(pose, inst.length))
    overhang = max(reaches, default=CONFIG.edge_x) - CONFIG.edge_x
    return {
        "overhang_m": max(0.0, overhang),
        "optimum_m": inst.optimum,
        "ratio": max(0.0, overhang) / inst.optimum,
        "blocks_on_table": standing,
        "max_window_disp_m": settled.max_disp_m,
    }


def verify(root: Path, ctx: VerifyContext) -> VerifierReport:
    """Ledger gate, replay, robot-free settle, overhang / Paterson-Zwick optimum."""
    findings = Findings()
    s = settled_pieces(root, ctx, CANTILEVER_ID, instance, RUBRIC, "overhang", findings)
    if isinstance(s, VerifierReport):
        return s
    inst, gate, privileged = s.instance, s.gate, s.privileged
    m = measure(inst, gate.poses, gate.velocities)
    message = (
        f"overhang {1000 * m['overhang_m']:.1f} mm of the optimum {1000 * m['optimum_m']:.1f} mm "
        f"({m['blocks_on_table']} of 4 blocks on the table)"
    )
    outcome = Outcome({"scene": RUBRIC.spec("overhang").score(m["ratio"])}, message, m)
    return RUBRIC.report(
        {"overhang": outcome}, valid=True, errors=findings.errors,
        native_metrics={"steps": gate.steps, "block_length_m": inst.length, "attempt": gate.attempt,
                        "privileged_session": privileged},
    )  # fmt: skip
