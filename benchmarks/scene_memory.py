"""Resident memory of a process that builds a new rendered scene per episode, as the stand-in's
served episodes do (target: after the renderer cache is full, at most 100 MB more over the remaining
scenes).

Usage: ``python -m benchmarks scene_memory [--scenes N]``. Builds N stand-in scenes in a row (one
reset each, which renders both views) and prints the process's RSS after each. The camera cache keeps
``MAX_RENDERERS`` renderers (``rle_design.control.cameras``), each a GL context holding its scene, so
RSS grows for the first ``MAX_RENDERERS / 2`` scenes and then stays flat. Exit status 1 if it keeps
growing.
"""

from __future__ import annotations

import argparse

from rle_design.control.cameras import MAX_RENDERERS
from rle_tasks.envs.standin import StandinEnv

TARGET_MB = 100.0


def rss_mb() -> float:
    """This process's resident set size [MB]."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS"):
                return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenes", type=int, default=12)
    args = p.parse_args()
    full = MAX_RENDERERS // 2  # two views per scene
    start = rss_mb()
    print(f"renderer cache {MAX_RENDERERS} (full after {full} scenes); RSS at start {start:.0f} MB")
    after = []
    for i in range(args.scenes):
        StandinEnv(i % 3).reset(i)
        after.append(rss_mb())
        print(f"scene {i + 1:3d}: RSS {after[-1]:7.0f} MB")
    if len(after) <= full:
        print(f"too few scenes to judge the plateau (need more than {full})")
        return 0
    growth = after[-1] - after[full - 1]
    print(
        f"growth after the cache filled: {growth:.0f} MB over {len(after) - full} scenes (target <= {TARGET_MB:.0f})"
    )
    return 0 if growth <= TARGET_MB else 1
