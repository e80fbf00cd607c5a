"""The card's numbers of family 08 (task id, budget), imported by the task and the verifier.

Budget (card): 2 h of development with 4 CPUs; the design and controller are verified on three arms
(stability batteries and two shelf loads each).
"""

from __future__ import annotations

from .public.scene import TASK_ID

__all__ = ["CPUS", "TASK_ID", "WALL_TIME_S"]

WALL_TIME_S = 2 * 3600.0
"""Development time [s] (card: 2 h)."""
CPUS = 4
