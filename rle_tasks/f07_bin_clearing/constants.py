"""The card's numbers of family 07 (task id, budget, hidden piles), imported by the task, the rubric and
the verifier.

Budget (card): 4 h of development with 4 CPUs. The verifier plays eight hidden piles of 120 s each
(quick: the first pile for 30 s).
"""

from __future__ import annotations

TASK_ID = "07-bin-clearing"
WALL_TIME_S = 4 * 3600.0
"""Development time [s] (card: 4 h)."""
CPUS = 4
VERIFIER_TIMEOUT_S = 3600.0
N_PILES = 8
"""Hidden piles of a full verification."""
QUICK_PILES = 1
"""Hidden piles of a quick (partial) verification (a full pile's 120 s, ``EPISODE_S``, is declared
in the workspace's ``public/env.py``)."""
QUICK_EPISODE_S = 30.0
"""Simulated time of the quick (partial) verification's one pile [s]."""
