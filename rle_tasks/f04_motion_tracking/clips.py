"""The clip of each family-04 task, and where clips come from: the shipped ones, or a directory named by
``RLE_F04_CLIPS``."""

from __future__ import annotations

import os
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHIPPED_CLIPS = HERE / "assets" / "clips"
TASK_CLIPS = {
    "04-dance": ("dance", "G1 dance clip"),
    "04-fight": ("fight", "G1 fight clip"),
    "04-fall-getup": ("fall-getup", "G1 fall and getup clip"),
    "04-run": ("run", "G1 run clip"),
    "04-sprint": ("sprint", "G1 sprint clip"),
}
"""Task id -> (clip style, title suffix)."""
CLIPS_ENV = "RLE_F04_CLIPS"
"""Environment variable naming a directory of ``<style>.npz`` clips that replace the shipped ones (e.g.
the card's LAFAN1 clips converted with ``rle import-motion``); used by the workspace and the verifier."""


def clip_path(style: str) -> Path:
    """The clip of a style: ``$RLE_F04_CLIPS/<style>.npz`` when that variable is set, else the shipped one."""
    root = os.environ.get(CLIPS_ENV)
    return (Path(root) if root else SHIPPED_CLIPS) / f"{style}.npz"
