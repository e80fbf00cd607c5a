"""Recipes (``solution.py`` files) shipped with the LIBERO foundation of family 05; see ``replay.py``."""

from pathlib import Path

MEAN_ACTION = Path(__file__).with_name("mean_action.py")
"""Baseline that must fail: the mean demonstrated action, whatever it sees."""
