"""What a submission exposes: the estimator protocol, the TorchScript model contract, the limits."""

from __future__ import annotations

from dataclasses import dataclass

from rle_design.sandbox import SandboxLimits
from rle_tasks.core.runtime.protocol import Budget, FunctionSpec, Protocol

ESTIMATOR = Protocol(
    "estimator",
    (
        FunctionSpec(
            "reset",
            "() -> None: forget all state (a new frame group or trajectory)",
            timeout_s=10.0,
            finite=False,
        ),
        FunctionSpec(
            "update",
            "obs: dict(rgb (240, 320, 3) uint8, t [s], K (3, 3) [px], T_world_cam (4, 4) [m], and for B/C/D "
            "depth (240, 320) float32 [m], valid (240, 320) bool) -> (x [m], y [m], theta [rad], shape_id)",
            returns=(4,),
            timeout_s=2.0,
        ),
    ),
)
"""Protocol of ``estimator.py`` (A, B, D) and of the verifier's model wrapper (C)."""
ESTIMATOR_BUDGET = Budget(max_faults=5, cpu_s=900.0, restart=True)
"""Faults and CPU time of one evaluation unit's estimator process."""
ESTIMATOR_LIMITS = SandboxLimits(cpu_seconds=900.0, memory_bytes=3 << 30, startup_timeout_s=60.0)
"""Sandbox limits of the estimator child (one thread: no thread or process creation)."""
MODEL_LIMITS = SandboxLimits(
    cpu_seconds=900.0, memory_bytes=6 << 30, startup_timeout_s=120.0, max_processes=64
)
"""Sandbox limits of the TorchScript child (torch starts helper threads; it runs one compute thread)."""
MAX_ELEMENTS = 20_000_000
"""Largest tensor element count of ``model.pt`` (parameters, buffers and constants)."""
SHAPE_IDS = (0, 1, 2)
"""Valid shape ids: T, C, F."""


@dataclass(frozen=True)
class Variant:
    """One of the four tasks.

    Attributes:
        task_id: Task id.
        letter: ``a`` ... ``d``.
        depth: Observations carry depth and validity.
        learned: The submission is ``model.pt`` (run by the verifier's wrapper).
        title: Short title.
    """

    task_id: str
    letter: str
    depth: bool
    learned: bool
    title: str

    @property
    def artifact(self) -> str:
        return "model.pt" if self.learned else "estimator.py"


VARIANTS = (
    Variant(
        "06-pose-a-rgb", "a", False, False, "Blind planar pose estimation, variant A, RGB-only estimator"
    ),
    Variant("06-pose-b-rgbd", "b", True, False, "Blind planar pose estimation, variant B, RGB-D estimator"),
    Variant(
        "06-pose-c-learned", "c", True, True, "Blind planar pose estimation, variant C, learned RGB-D model"
    ),
    Variant(
        "06-pose-d-agnostic",
        "d",
        True,
        False,
        "Blind planar pose estimation, variant D, method-agnostic estimator",
    ),
)


def variant(task_id: str) -> Variant:
    for v in VARIANTS:
        if v.task_id == task_id:
            return v
    raise ValueError(
        f"unknown task '{task_id}'. Tasks of family 06: {', '.join(v.task_id for v in VARIANTS)}"
    )
