"""Verifier of ``03-balance-coins``: the sealed session ledger, replayed, settled without the robot.

Protocol:

1. ``ledger.jsonl`` in the submission must be a sealed, authentic ledger of this task under the
   ledger key of the verifier secret (``verify_ledger``); otherwise score 0 (cap ``ledger``) with the
   verdict's code and reason.
2. The instance is drawn from the secret (``BalanceInstance.draw``) and the ledger's resets and
   actions replayed on its environment (``rle_design.control.replay``); a ledger recorded on another
   scene or diverging in time scores 0 with the replay's code. The weighings are read from the
   replayed state (``balance_env`` counts them while stepping, exactly as the server did).
3. The final cube poses and balance angles are copied into the robot-free scene, the beam locked,
   and the scene settled for ``SETTLE_S``: a cube held by the gripper falls.
4. A cube is on the mat when its centre lies over the mat and it rests on the table top (centre
   height within ``REST_TOL`` of half a cube). Score: 0 unless the heavy cube is the only cube on the
   mat; then 1 for w <= 2 weighings, else 2 / w.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from rle_tasks.core.report import Findings, VerifierReport
from rle_tasks.core.scoring import CheckpointSpec, Fraction, Outcome, Rubric
from rle_tasks.core.secrets import Secret, derive_rng
from rle_tasks.core.task import VerifyContext

from . import balance_scene as bs
from .balance_env import (
    MAT_CENTRE,
    MAT_HALF,
    TABLE,
    TASK_ID,
    WEIGHINGS,
    BalanceInstance,
    make_env,
    robotless_spec,
)
from .session import LEDGER_FILE, replay_ledger

SETTLE_S = 1.0
"""Robot-free settling time [s]: a dropped 30 mm cube lands and stops well within it."""
REST_TOL = 0.003
"""Tolerance on a resting cube's centre height [m] (contact penetration is < 1 mm)."""
OPTIMAL_WEIGHINGS = 2
"""ceil(log3 9): the fewest weighings that always find the heavy cube."""

RUBRIC = Rubric(
    task_id=TASK_ID,
    family="03",
    workflow="interactive_control",
    variants=("scene",),
    checkpoints=(
        CheckpointSpec(
            "identified",
            1.0,
            "only the heavy cube rests on the mat after robot-free settling; w = weighings in the ledger",
            Fraction("0 unless only the heavy cube is on the mat; then 1 for w <= 2, else 2/w"),
        ),
    ),
)


def weighing_score(heavy_only: bool, weighings: int) -> float:
    """The card's score: 0 unless only the heavy cube reached the mat; then 1 for w <= 2, else 2/w."""
    if not heavy_only:
        return 0.0
    return 1.0 if weighings <= OPTIMAL_WEIGHINGS else OPTIMAL_WEIGHINGS / weighings


def instance(secret: Secret) -> BalanceInstance:
    """The instance of a secret."""
    return BalanceInstance.draw(derive_rng(secret, TASK_ID, "instance"))


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
    """Copy the cubes and balance of a replayed state into the robot-free scene and settle it."""
    spec = robotless_spec(inst)
    m2 = spec.compile()
    d2 = mujoco.MjData(m2)
    for j in range(m2.njnt):
        name = m2.joint(j).name
        src = model.joint(name).id
        n = 7 if m2.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE else 1
        d2.qpos[m2.jnt_qposadr[j] : m2.jnt_qposadr[j] + n] = data.qpos[
            model.jnt_qposadr[src] : model.jnt_qposadr[src] + n
        ]
    mujoco.mj_forward(m2, d2)
    bs.lock(m2, d2)
    for _ in range(int(round(SETTLE_S / m2.opt.timestep))):
        mujoco.mj_step(m2, d2)
    pos = np.array([d2.xpos[m2.body(bs.cube_name(i)).id] for i in range(bs.N_CUBES)])
    half = inst.cubes.size / 2
    on = tuple(
        i
        for i, p in enumerate(pos)
        if abs(p[0] - MAT_CENTRE[0]) <= MAT_HALF
        and abs(p[1] - MAT_CENTRE[1]) <= MAT_HALF
        and abs(p[2] - (TABLE.top_z + half)) <= REST_TOL
    )
    return FinalScene(on, pos)


def _invalid(code: str, message: str, findings: Findings) -> VerifierReport:
    findings.add_error(code, message, LEDGER_FILE)
    return RUBRIC.report(
        {"identified": Outcome({"scene": 0.0}, f"no valid session: {message}")},
        valid=False,
        errors=findings.errors,
        native_metrics={"ledger": code},
    )


def verify(root: Path, ctx: VerifyContext) -> VerifierReport:
    """Verify a submission directory holding the session's ``ledger.jsonl`` (module docstring)."""
    findings = Findings()
    inst = instance(ctx.secret)
    gate = replay_ledger(root, ctx.secret, TASK_ID, make_env(inst, image_size=None))
    if not gate.ok:
        return _invalid(gate.code, gate.message, findings)
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
    native = {"weighings": weighings, "steps": gate.steps, "actions": gate.actions, "settle_s": SETTLE_S}
    return RUBRIC.report(
        {"identified": Outcome({"scene": score}, message, measured)},
        valid=True,
        errors=findings.errors,
        native_metrics=native,
    )
