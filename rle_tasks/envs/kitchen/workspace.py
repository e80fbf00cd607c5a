"""Lays the kitchen harness of a level into an agent workspace (``harness/`` beside ``client.py``)."""

from __future__ import annotations

import shutil
from pathlib import Path

__all__ = ["HARNESS_FILES", "lay_out_harness"]

HARNESS = Path(__file__).resolve().parent / "harness"
HARNESS_FILES: dict[int, tuple[str, ...]] = {
    1: ("robot.py",),
    2: ("robot.py", "geometry.py", "perception.py", "motion.py"),
    3: ("robot.py", "geometry.py", "perception.py", "motion.py", "world.py"),
}
"""Modules of each harness level (each level has those of the levels below)."""
_INIT = '"""The kitchen harness of level {level}: {modules}."""\n'


def lay_out_harness(workspace: Path, level: int) -> list[Path]:
    """Copy the level's modules into ``workspace/harness`` (replacing an older copy); returns the files."""
    if level not in HARNESS_FILES:
        raise ValueError(f"harness level must be one of {sorted(HARNESS_FILES)}, got {level}")
    dest = Path(workspace) / "harness"
    if dest.exists():
        shutil.rmtree(dest)
    dest.mkdir(parents=True)
    files = [dest / "__init__.py"]
    names = HARNESS_FILES[level]
    files[0].write_text(_INIT.format(level=level, modules=", ".join(n[:-3] for n in names)))
    for name in names:
        shutil.copyfile(HARNESS / name, dest / name)
        files.append(dest / name)
    return files
