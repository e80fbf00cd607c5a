"""The card's numbers of family 09 (task id, budget, the device's mass target), imported by the task, the
device checks and the verifier.

Budget (card): 3 h of development with 4 CPUs; one leader for each of the three robots.
"""

from __future__ import annotations

TASK_ID = "09-gello"
WALL_TIME_S = 3 * 3600.0
"""Development time [s] (card: 3 h)."""
CPUS = 4
VERIFIER_TIMEOUT_S = 600.0
MAX_MASS_KG = 2.30
"""The card's device mass cap [kg]: above it the deduction grows linearly with the excess."""
HARD_MASS_KG = 3.00
"""Mass at which the over-mass deduction is full (0.10) and beyond which a leader is refused [kg]
(README: derivation)."""
