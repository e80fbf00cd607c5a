"""Regenerate the stock leader assets: ``python -m rle_tasks.f09_gello.solutions.make_assets``.

Writes ``assets/<robot>/lead.xml`` and ``assets/<robot>/meshes/*.stl`` for every robot and prints the
device mass. Meshes every leader shares (the base plate) are stored once, in ``assets/common/meshes``,
and each robot's ``meshes/<name>`` is a relative symlink to it: the repository and the package hold one
copy, while every directory that is copied out (workspace, solutions, export) stays self-contained
because copies follow the link.
"""

from __future__ import annotations

import os
from pathlib import Path

from rle_tasks.f09_gello.assembly import build_assembly, write_assembly
from rle_tasks.f09_gello.leaders import ROBOTS

ASSET_DIR = Path(__file__).resolve().parents[1] / "assets"
COMMON = ASSET_DIR / "common" / "meshes"


def _share(meshes: dict[str, dict[str, bytes]]) -> set[str]:
    """Mesh names whose bytes are identical for every robot."""
    names = set.intersection(*(set(m) for m in meshes.values()))
    return {n for n in names if len({m[n] for m in meshes.values()}) == 1}


def main() -> None:
    written = {}
    for robot in ROBOTS:
        asm = build_assembly(robot)
        for name in asm.meshes:
            p = ASSET_DIR / robot / "meshes" / name
            if p.is_symlink():
                p.unlink()  # write_assembly writes real files
        path = write_assembly(asm, ASSET_DIR / robot)
        written[robot] = {n: (path.parent / "meshes" / n).read_bytes() for n in asm.meshes}
        print(f"{robot}: {path} mass {asm.total_mass:.3f} kg")
    COMMON.mkdir(parents=True, exist_ok=True)
    for name in sorted(_share(written)):
        (COMMON / name).write_bytes(written[ROBOTS[0]][name])
        for robot in ROBOTS:
            link = ASSET_DIR / robot / "meshes" / name
            link.unlink()
            os.symlink(os.path.relpath(COMMON / name, link.parent), link)
        print(f"shared: meshes/{name} -> {COMMON / name}")


if __name__ == "__main__":
    main()
