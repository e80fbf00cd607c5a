"""Build time of the pocket cube's quarter-turn distance table, and the cached load with its checksum.

Usage: ``.venv/bin/python benchmarks/cube_table.py``. Prints the move-table time, the breadth-first
build time (3,674,160 states), and the time to load the cached table and check its SHA-256. Builds into
a temporary cache directory, so the user's cache is left alone. Exit status 1 when the build takes
more than 10 s (the bound under which the full table stays in the fast tests).
"""

from __future__ import annotations

import os
import sys
import tempfile
import time

from rle_tasks.f03_physical_reasoning.cube import distance
from rle_tasks.f03_physical_reasoning.cube.coords import move_tables

LIMIT_S = 10.0


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["RLE_CACHE_DIR"] = tmp
        t0 = time.perf_counter()
        move_tables()
        t1 = time.perf_counter()
        distance.distance_table.cache_clear()
        table = distance.distance_table()  # cache empty: builds, checks, writes
        t2 = time.perf_counter()
        distance.distance_table.cache_clear()
        distance.distance_table()  # loads and checks
        t3 = time.perf_counter()
        distance.distance_table.cache_clear()
    build = t2 - t1
    print(f"move tables              {t1 - t0:6.2f} s")
    print(
        f"breadth-first build      {build:6.2f} s  ({table.size:,} states, max distance {int(table.max())})"
    )
    print(f"load + sha256 check      {t3 - t2:6.3f} s")
    return 0 if build <= LIMIT_S else 1


if __name__ == "__main__":
    sys.exit(main())
