"""Regenerate the stock leader assets: ``python -m rle_tasks.f09_gello.solutions.make_assets``.

Writes ``assets/<robot>/lead.xml`` and ``assets/<robot>/meshes/*.stl`` for every robot and prints
the device mass and the peak shoulder gravity torque over the public workspace grid.
"""

from __future__ import annotations

from pathlib import Path

from rle_tasks.f09_gello.assembly import build_assembly, write_assembly
from rle_tasks.f09_gello.leaders import ROBOTS

ASSET_DIR = Path(__file__).resolve().parent / "assets"


def main() -> None:
    for robot in ROBOTS:
        asm = build_assembly(robot)
        path = write_assembly(asm, ASSET_DIR / robot)
        print(f"{robot}: {path} mass {asm.total_mass:.3f} kg")


if __name__ == "__main__":
    main()
