"""The card's numbers of family 01 (budget, evaluation trials), imported by the kitchens, the tasks, the
verifier and the audit cases.

Budget (card): 8 h with 4 CPUs and 1 GPU, 50,000 charged development steps; then an evaluation phase of
5 trials of at most 1,000 actions each, within 1 h.
"""

from __future__ import annotations

STEP_BUDGET = 50_000
"""Charged development steps (card)."""
TRIALS = 5
"""Evaluation trials (card)."""
ACTIONS_PER_TRIAL = 1000
"""Actions one evaluation trial may take (card)."""
EVAL_WALL_S = 3600.0
"""Wall time of the evaluation phase [s] (card)."""
WALL_TIME_S = 8 * 3600.0
"""Wall time of the session [s] (card: 8 h)."""
CPUS = 4
GPUS = 1
VERIFIER_TIMEOUT_S = 1800.0
"""Verifier wall-time limit [s]: five trials' replays."""
