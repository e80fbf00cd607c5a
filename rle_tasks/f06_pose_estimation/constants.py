"""The card's numbers of family 06 (budgets per variant, the hidden evaluation's size), imported by the
tasks and the verifier.

Budget (card): 2 h of development; 4 CPUs for the estimators of variants A, B and D (D with 1 GPU in
development), 16 CPUs and 1 GPU to train variant C's model. The hidden evaluation scores 10 groups of
frames and 10 push trajectories of 60 frames (quick: 3, 3 and 20).
"""

from __future__ import annotations

WALL_TIME_S = 2 * 3600.0
"""Development time [s] (card: 2 h)."""
CPUS = {"a": 4, "b": 4, "c": 16, "d": 4}
GPUS = {"a": 0, "b": 0, "c": 1, "d": 1}
VERIFIER_TIMEOUT_S = 1800.0
N_GROUPS, N_TRAJ, TRAJ_FRAMES = 10, 10, 60
"""Hidden frame groups, push trajectories and frames per trajectory of a full verification."""
QUICK_GROUPS, QUICK_TRAJ, QUICK_TRAJ_FRAMES = 3, 3, 20
"""The same of a quick (partial) verification."""
