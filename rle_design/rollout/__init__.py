"""Rollout layer: the episode loop, its terms, and environment definitions shared by development and
evaluation."""

from rle_design.rollout.env import EnvDefinition, advance
from rle_design.rollout.episode import ControlFn, Episode, RolloutError, run_episode
from rle_design.rollout.terms import (
    ContactBetween,
    Event,
    HoldAtTarget,
    SimulationWarnings,
    Term,
    TiltLimit,
    root_tilt,
)

__all__ = [
    "ContactBetween",
    "ControlFn",
    "EnvDefinition",
    "Episode",
    "Event",
    "HoldAtTarget",
    "RolloutError",
    "SimulationWarnings",
    "Term",
    "TiltLimit",
    "advance",
    "root_tilt",
    "run_episode",
]
