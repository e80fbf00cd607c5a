"""Wall time of a full 09-gello verification of the shipped reference (target: < 30 s on 2 cores).

Usage: ``.venv/bin/python -m benchmarks f09_verify [--quick]``. Prints the elapsed time, the score and
the per-variant scores. Exit status 1 if the full verification takes 30 s or more.
"""

from __future__ import annotations

import argparse
import sys
import time

TARGET_S = 30.0


def main() -> int:
    from rle_tasks.core.registry import get_task
    from rle_tasks.core.runtime.secrets import load_secret
    from rle_tasks.core.solutions import materialise
    from rle_tasks.core.task import VerifyContext
    from rle_tasks.core.verify import run_verify

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(sys.argv[1:])
    task = get_task("09-gello")
    ref = materialise(task, "reference")
    t0 = time.perf_counter()
    report, internal = run_verify(task, ref, VerifyContext(secret=load_secret(), quick=args.quick))
    elapsed = time.perf_counter() - t0
    per = report.native_metrics.get("variant_score", {})
    print(
        f"09-gello reference ({'quick' if args.quick else 'full'}): {elapsed:.2f} s, score {report.score:.3f}, "
        + ", ".join(f"{k} {v:.3f}" for k, v in per.items())
    )
    return 0 if elapsed < TARGET_S and not internal else 1


if __name__ == "__main__":
    raise SystemExit(main())
