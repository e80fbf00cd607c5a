"""Build-time: the score a candidate placement of the reference leaders loses, as the rubric counts it.

``_loss`` (the greedy's ranking) sums motion clearance, the passive residual and hold
(``hold_failure``: the fraction of poses at which an unbalanced moment slips the servo's Coulomb
friction ``SERVO_FRICTION``), the servo headroom and combined hold and push beyond the servo limit,
and the backdrive the unbalanced moment and added inertia cost; ``_search_loss`` (the joint search's
and the coordinate descent's) counts clearance at its full slope beyond the 5 % fail value too.
"""

from __future__ import annotations

import numpy as np

from rle_tasks.f09_gello.scoring import SERVO_LIMIT

SERVO_FRICTION = 0.0128
"""Coulomb friction of the stock servo [N m] (servo catalog, XL330-M288-T)."""


def hold_failure(moment: float, friction: float = SERVO_FRICTION) -> float:
    """Fraction of poses at which a joint carrying a gravity moment of peak ``moment`` [N m] slips
    its servo's Coulomb ``friction`` [N m] [1].

    The moment of a rigid subtree about a joint is ``moment x sin(theta)``, theta the angle between
    the joint's lever and the vertical; for theta uniform over a turn, ``|sin(theta)| > f / moment``
    holds on ``1 - (2 / pi) asin(f / moment)`` of it. A joint that slips at rest drifts far beyond the
    hold's 0.1 rad fail value in 2 s, so this is the passive hold's loss fraction.
    """
    if moment <= friction:
        return 0.0
    return 1.0 - 2.0 / np.pi * float(np.arcsin(friction / moment))


def _loss(collisions: float, worst_residual: float, effort: np.ndarray | None = None) -> float:
    """Score lost to motion clearance, the passive residual and hold, and added inertia, as the
    rubric counts them [1].

    Clearance: 0.10 x fraction / 0.05, as the checkpoint counts it up to its 5 % fail value, and a
    tenth of that slope beyond it (the checkpoint gives nothing there, but a greedy that stopped
    counting there would never bring the sum of several joints' collisions back under it; at the
    full slope it dropped xarm7's joint 3 and 6 weights, 0.55 N m, to clear 10 % more poses);
    residual: the passive-residual
    checkpoint (0.02 to 0.35 N m); hold: 0.10 x the fraction of poses at which the unbalanced
    moment slips the servo friction (``hold_failure``; issue 45: the linear ramp it replaces put a
    0.024 N m joint at 0.02, the verifier measured 0.07); the servo-headroom checkpoint and the
    combined hold and push recovery, which the clipped feedforward loses once the moment exceeds the
    0.35 N m servo limit (issue 45: a greedy without them left xarm7's joint 3 at 0.55 N m to drop
    contacts); inertia: both submitted-arm backdrive
    checkpoints (0.03 to 0.35 N m) on the servo friction plus ``effort`` (per pose, the worst joint's
    ``ACCEL_REF x`` added inertia [N m]), the passive one also on the unbalanced moment.
    """
    clear = 0.1 * min(collisions, 0.05) / 0.05 + 0.1 * max(collisions - 0.05, 0.0) / 0.5
    resid = 0.1 * float(np.clip((worst_residual - 0.02) / 0.33, 0.0, 1.0))
    hold = 0.1 * hold_failure(worst_residual)
    # the adapted feedforward takes the rest, clipped at the servo limit: headroom (0.5 to 1.5 x
    # the limit), and the combined hold and push lost where the moment beats limit and friction
    head = 0.1 * float(np.clip(worst_residual / SERVO_LIMIT - 0.5, 0.0, 1.0))
    combined = 0.2 * hold_failure(worst_residual, SERVO_LIMIT + SERVO_FRICTION)
    # backdrive: the passive checkpoint also breaks away the unbalanced moment, on average
    # (2 / pi) x its peak; the combined one has it carried by the feedforward
    effort = np.zeros(1) if effort is None else effort
    moment = 2.0 / np.pi * worst_residual
    back = 0.1 * float(np.mean(np.clip((SERVO_FRICTION + moment + effort - 0.03) / 0.32, 0.0, 1.0)))
    back += 0.1 * float(np.mean(np.clip((SERVO_FRICTION + effort - 0.03) / 0.32, 0.0, 1.0)))
    return clear + resid + hold + head + combined + back


def _search_loss(collisions: float, worst_residual: float, effort: np.ndarray) -> float:
    """``_loss`` with clearance at its full slope beyond the 5 % fail value too (the joint search
    ranks combinations by how many poses they clear, wherever they stand)."""
    full = 0.1 * collisions / 0.05
    return _loss(0.0, worst_residual, effort) + full
