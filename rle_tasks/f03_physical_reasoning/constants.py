"""The card's numbers of family 03 (task ids, budgets, wall times), imported by every task's modules.

Budget (card): 9 h, 1 GPU, 50,000 charged steps in one continuous attempt for the tower, the cantilever,
the balance and the cube; 12,000 steps per box and 1 h in all for the hidden centre of mass. Resets
restore the same scene.
"""

from __future__ import annotations

TOWER_ID = "03-tower"
CANTILEVER_ID = "03-cantilever"
BALANCE_ID = "03-balance-coins"
HIDDEN_COM_ID = "03-hidden-com"
CUBE_ID = "03-pocket-cube"

STEP_BUDGET = 50_000
"""Charged steps of the one continuous attempt (card)."""
WALL_TIME_S = 9 * 3600.0
"""Wall time of the one continuous attempt [s] (card: 9 h)."""

STEPS_PER_BOX = 12_000
"""Hidden centre of mass: the card's budget per box [steps]."""
N_BOXES = 3
HIDDEN_COM_STEPS = STEPS_PER_BOX * N_BOXES
"""Hidden centre of mass: the card's 12,000 steps per box for the three boxes of one session; the
environment refuses an answer given more than 12,000 steps after the previous one."""
HIDDEN_COM_WALL_TIME_S = 3600.0
"""Hidden centre of mass: the card's "1 h total" [s]: the session refuses steps after it, and the
verifier requires a session that was limited to it."""

CPUS = 4
GPUS = 1
VERIFIER_TIMEOUT_S = 1800.0
"""Verifier wall-time limit [s]: a replay of 50,000 steps with its settle fits in a few minutes."""
