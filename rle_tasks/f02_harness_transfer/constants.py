"""The card's numbers of family 02 (budgets of the development trial and of each fresh agent)."""

from __future__ import annotations

STEP_BUDGET = 75_000
"""Charged development steps (card)."""
TRIALS = 5
"""Fresh agents (card)."""
AGENT_STEPS = 5_000
"""Steps of one fresh agent (card)."""
AGENT_WALL_S = 3600.0
"""Time of one fresh agent [s] (card)."""
