"""Verifier of ``03-balance-coins``: the sealed session ledger, replayed, settled without the robot.

Protocol:

1. ``ledger.jsonl`` in the submission must be a sealed, authentic ledger of this task under the
   ledger key of the verifier secret (``verify_ledger``); otherwise score 0 (cap ``ledger``) with the
   verdict's code and reason.
2. The instance is drawn from the secret (``BalanceInstance.draw``) and the ledger's resets and
   actions replayed on its environment (``rle_design.control.replay``); a ledger recorded on another
   scene or diverging in time scores 0 with the replay's code. The weighings are read from the
   replayed state (``env`` counts them while stepping, exactly as the server did).
3. The final cube poses and velocities and the balance's angles and rates are copied into the
   robot-free scene, the beam locked, and the scene settled for ``SETTLE_S``: a cube held by the
   gripper falls, a cube still sliding at the end slides on.
4. A cube is on the mat when its centre lies over the mat, it lies on the table top (centre height
   within ``REST_TOL`` of half a cube) and it is at rest (``scene.at_rest`` over the last
   ``scene.REST_WINDOW_S``: moved under ``REST_DISP_M`` and turned under ``REST_ANGLE``). Score: 0 unless the heavy cube is the only cube on the
   mat; then 1 for w <= 2 weighings, else 2 / w.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.runtime.secrets import Secret, derive_rng
from rle_tasks.core.scoring import Outcome
from rle_tasks.core.task import VerifyContext

from ..constants import BALANCE_ID, STEP_BUDGET, WALL_TIME_S
from ..scene import REST_ANGLE, REST_DISP_M, REST_SAMPLE_S, REST_WINDOW_S, rest_motion
from ..session import LEDGER_FILE, invalid_report, open_ledger, replay_ledger, tabletop_limits
from . import scene as bs
from .env import MAT_CENTRE, MAT_HALF, TABLE, WEIGHINGS, BalanceInstance, make_env, robotless_spec
from .scoring import RUBRIC, weighing_score

__all__ = ["LEDGER_FILE", "SETTLE_S", "FinalScene", "instance", "settle_final", "verify"]

SETTLE_S = 3.0
"""Robot-free settling time [s]: a cube dropped from 5 cm lands within 0.1 s and stops well within
1 s; the last ``scene.REST_WINDOW_S`` = 2 s of it judge rest (``scene.at_rest``)."""
REST_TOL = 0.003
"""Tolerance on a resting cube's centre height [m] (contact penetration is < 1 mm)."""


def instance(secret: Secret) -> BalanceInstance:
    """The instance of a secret."""
    return BalanceInstance.draw(derive_rng(secret, BALANCE_ID, "instance"))


@dataclass(frozen=True)
class FinalScene:
    """What the settled, robot-free final scene shows.

    Attributes:
        on_mat: Indices of the cubes resting on the mat.
        cube_pos: Settled cube centres (9 x 3) [m].
    """

    on_mat: tuple[int, ...]
    cube_pos: np.ndarray


def settle_final(inst: BalanceInstance, model: mujoco.MjModel, data: mujoco.MjData) -> FinalScene:
    """Copy the cubes and balance of a replayed state (positions and velocities) into the robot-free
    scene, lock the beam, settle it and judge rest over the last ``REST_WINDOW_S``."""
    spec = robotless_spec(inst)
    m2 = spec.compile()
    d2 = mujoco.MjData(m2)
    for j in range(m2.njnt):
        src = model.joint(m2.joint(j).name).id
        free = m2.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE
        nq, nv = (7, 6) if free else (1, 1)
        d2.qpos[m2.jnt_qposadr[j] : m2.jnt_qposadr[j] + nq] = data.qpos[
            model.jnt_qposadr[src] : model.jnt_qposadr[src] + nq
        ]
        d2.qvel[m2.jnt_dofadr[j] : m2.jnt_dofadr[j] + nv] = data.qvel[
            model.jnt_dofadr[src] : model.jnt_dofadr[src] + nv
        ]
    mujoco.mj_forward(m2, d2)
    bs.lock(m2, d2)
    bodies = [m2.body(bs.cube_name(i)).id for i in range(bs.N_CUBES)]
    dt = m2.opt.timestep
    n_sample = max(1, int(round(REST_SAMPLE_S / dt)))
    n_window = n_sample * int(round(REST_WINDOW_S / (n_sample * dt)))
    mujoco.mj_step(m2, d2, int(round(SETTLE_S / dt)) - n_window)
    start = [(d2.xpos[b].copy(), d2.xquat[b].copy()) for b in bodies]
    resting = [True] * bs.N_CUBES
    for _ in range(n_window // n_sample):
        mujoco.mj_step(m2, d2, n_sample)
        mujoco.mj_kinematics(m2, d2)  # xpos/xquat of the state reached
        for i, b in enumerate(bodies):
            disp, angle = rest_motion(*start[i], d2.xpos[b], d2.xquat[b])
            resting[i] = resting[i] and disp < REST_DISP_M and angle < REST_ANGLE
    pos = np.array([d2.xpos[b] for b in bodies])
    half = inst.cubes.size / 2
    on = tuple(
        i
        for i, p in enumerate(pos)
        if abs(p[0] - MAT_CENTRE[0]) <= MAT_HALF
        and abs(p[1] - MAT_CENTRE[1]) <= MAT_HALF
        and abs(p[2] - (TABLE.top_z + half)) <= REST_TOL
        and resting[i]
    )
    return FinalScene(on, pos)


def verify(root: Path, ctx: VerifyContext) -> VerifierReport:
    """Verify a submission directory holding the session's ``ledger.jsonl`` (module docstring)."""
    findings = Findings()
    opened = open_ledger(root, ctx.secret, BALANCE_ID, tabletop_limits(STEP_BUDGET, WALL_TIME_S), ctx.attempt)
    inst = instance(opened.secret)
    gate = replay_ledger(opened, make_env(inst, image_size=None))
    if not gate.ok:
        return invalid_report(RUBRIC, gate.code, gate.message, findings)
    model, data = gate.model, gate.data
    weighings = int(data.userdata[WEIGHINGS])
    final = settle_final(inst, model, data)
    heavy_only = final.on_mat == (inst.heavy,)
    score = weighing_score(heavy_only, weighings)
    if not final.on_mat:
        message = "no cube rests on the mat"
    elif heavy_only:
        message = f"the heavy cube alone rests on the mat after {weighings} weighing(s)"
    elif inst.heavy in final.on_mat:
        message = f"cubes {list(final.on_mat)} rest on the mat: the heavy cube is not alone"
    else:
        message = f"cube(s) {list(final.on_mat)} rest on the mat: not the heavy cube"
    measured = {"weighings": weighings, "cubes_on_mat": list(final.on_mat), "heavy_only": heavy_only}
    native = {
        "weighings": weighings,
        "steps": gate.steps,
        "actions": gate.actions,
        "settle_s": SETTLE_S,
        "attempt": gate.attempt,
    }
    return RUBRIC.report(
        {"identified": Outcome({"scene": score}, message, measured)},
        valid=True,
        errors=findings.errors,
        native_metrics=native,
    )
