"""The card's numbers of family 05 (task ids, budget, episode sets, completion), imported by the tasks,
the rubric and the verifier.

Budget (card): 4 h of development with 48 CPUs, 1 GPU and 64 GiB; the verifier retrains the recipe and
plays each track's fixed episode set (LIBERO-10: 10 tasks x 50 official initial states; the RoboTwin
tracks on the bimanual stand-in: 300 and 225 episodes).
"""

from __future__ import annotations

OPEN_ID = "05-libero-open"
ROBUST_ID = "05-libero-robust"
STANDIN_OPEN_ID = "05-robotwin-open"
STANDIN_ROBUST_ID = "05-robotwin-robust"

WALL_TIME_S = 4 * 3600.0
"""Development time [s] (card: 4 h)."""
CPUS = 48
GPUS = 1
MEMORY_MB = 64 * 1024
VERIFIER_TIMEOUT_S = 12 * 3600.0
"""Verifier wall-time limit [s]: the retraining and 500 LIBERO episodes."""

N_TASKS = 10
INITS_PER_TASK = 50
"""LIBERO's official initial states per task (LIBERO-PRO's perturbed suites have as many)."""
EPISODES = 500
"""Episodes of each LIBERO track's fixed set (the card)."""
STANDIN_TASKS = 3
STANDIN_PER_TASK = {STANDIN_OPEN_ID: 100, STANDIN_ROBUST_ID: 75}
"""Layouts per stand-in task: 300 and 225 episodes (the card's RoboTwin sets)."""
EPISODE_SETS = {
    OPEN_ID: EPISODES,
    ROBUST_ID: EPISODES,
    STANDIN_OPEN_ID: STANDIN_TASKS * STANDIN_PER_TASK[STANDIN_OPEN_ID],
    STANDIN_ROBUST_ID: STANDIN_TASKS * STANDIN_PER_TASK[STANDIN_ROBUST_ID],
}
"""Episodes of each track's fixed set (the card: LIBERO 500 / 500, RoboTwin 300 / 225; the RoboTwin
tracks run on the bimanual stand-in); the card's completion thresholds 475, 475, 285 and 214 are
``scoring.required_complete`` of these."""
COMPLETION = 475 / 500
"""Fraction of the episode set that must complete (the card: at least 475 of 500) [1]."""
QUICK_EPISODES = 2
"""Episodes of a quick (partial) verification on LIBERO: ``make demo`` and the golden table."""
STANDIN_QUICK_EPISODES = 12
"""Episodes of a quick verification on the stand-in (four of each task; an episode costs seconds,
not LIBERO's minute)."""
