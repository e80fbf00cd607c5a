"""Development workspace of the ``06-pose-*`` tasks: the instruction, ``pose_client.py`` and the served renderer.

``make_dev_env`` writes the client and returns a ``ServedSession`` (``rle_tasks.core.runtime.devservice``); ``rle dev`` starts it (core
``layout_workspace``) with the ledger key and a ledger file outside the workspace, unless it runs with
``--no-serve``. The server process (``service.py``) holds the scene; the workspace never receives
meshes, block dimensions or shape labels.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from rle_tasks.core.runtime.devservice import CLIENT_ADDRESS, ServedSession

HERE = Path(__file__).resolve().parent

_CLIENT = '''"""Development client of {task_id} (written by `rle dev`).

    from pose_client import connect
    with connect() as dev:
        pairs = dev.frames(seed=0, n=10)          # free: [(obs, label), ...] independent frames
        pairs = dev.frames(seed=1, n=10, raised=True)  # stick out of the way
        pairs = dev.episode(seed=2, n=60)         # free: a push episode, 10 Hz
        report = dev.evaluate()                   # charged: your current {artifact} on the design set
        dev.info()                                # evaluations used and left (per attempt)
        dev.seal()                                # ends the session: seals the ledger, stops the server

evaluate() runs the files at the root of this workspace (the directory of this file), as the
verifier reads a submission directory; its report gives the score, fps as the score counts it
(rounded, capped at 10, as `rle verify` reports it), fps_measured, and the files' sha256.

obs: rgb (240, 320, 3) uint8, t [s], K (3, 3), T_world_cam (4, 4){depth}.
label: (x [m], y [m], theta [rad]) with Gaussian noise (1 mm, 0.01 rad); shapes are withheld
(ids 0, 1, 2 = T, C, F). Budget: {evaluations} design-set evaluations per attempt, every request
recorded in a sealed ledger kept outside this workspace; development time 2 h.
"""

import hashlib
import tempfile
from multiprocessing.connection import Client
from pathlib import Path

import warnings

with warnings.catch_warnings():  # the simulator runs in the server: this process's BLAS kernels do not matter
    warnings.simplefilter("ignore", RuntimeWarning)
    from rle_design.ledger.server import decode, encode
{address}

class DevClient(_Connection):
    def frames(self, seed, n=10, raised=False):
        return [(p["obs"], p["label"]) for p in self._request("frames", {{"seed": seed, "n": n, "raised": raised}})]

    def episode(self, seed, n=60):
        return [(p["obs"], p["label"]) for p in self._request("episode", {{"seed": seed, "n": n}})]

    def evaluate(self):
        return self._request("evaluate")


def connect():
    return DevClient()
'''


def make_dev_env(task_id: str, workspace: Path) -> ServedSession:
    """Write ``pose_client.py`` and ``calibration.json`` into ``workspace``; return the (not yet started) server."""
    from .contract import variant
    from .scene import CALIBRATION_FILE
    from .service import EVALUATIONS

    v = variant(task_id)
    ws = Path(workspace)
    ws.mkdir(parents=True, exist_ok=True)
    depth = ", depth (240, 320) float32 [m], valid (240, 320) bool" if v.depth else ""
    shutil.copyfile(HERE / "assets" / CALIBRATION_FILE, ws / CALIBRATION_FILE)
    (ws / "pose_client.py").write_text(
        _CLIENT.format(
            task_id=task_id, artifact=v.artifact, depth=depth, evaluations=EVALUATIONS, address=CLIENT_ADDRESS
        )
    )
    return ServedSession(
        "rle_tasks.f06_pose_estimation.service:open_session",
        {"task_id": task_id, "workspace": str(ws)},
        name=f"rle-dev-{task_id}",
        client="pose_client",
    )
