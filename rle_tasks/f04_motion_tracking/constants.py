"""The card's numbers of family 04 (task ids, budget, evaluation size), imported by the task, the rubric
and the verifier.

Budget (card): 4 h of development with 4 CPUs and 1 GPU; the verifier plays eight hidden seeds (two in
quick mode) of the 20 s clip.
"""

from __future__ import annotations

TASK_IDS = ("04-dance", "04-fight", "04-fall-getup", "04-run", "04-sprint")
WALL_TIME_S = 4 * 3600.0
"""Development time [s] (card: 4 h)."""
CPUS = 4
GPUS = 1
VERIFIER_TIMEOUT_S = 600.0
"""Verifier wall-time limit [s]: eight seeds of the full clip take about 35 s with one job."""
N_SEEDS = 8
"""Hidden seeds of a full verification (card: eight perturbed rollouts)."""
QUICK_SEEDS = 2
"""Hidden seeds of a quick verification (partial)."""
