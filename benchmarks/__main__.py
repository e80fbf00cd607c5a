"""``python -m benchmarks [--list | NAME [ARGS...]]``: list, run one, or (no arguments) run every benchmark.

A benchmark is a module of this package with a ``main() -> int`` that parses ``sys.argv``; its exit
status is non-zero when it misses its target.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys
from pathlib import Path

import rle_design  # noqa: F401  (pins the BLAS kernels and the GL backend before a benchmark loads numpy)


def names() -> list[str]:
    """Benchmark module names, sorted."""
    return sorted(
        m.name for m in pkgutil.iter_modules([str(Path(__file__).parent)]) if not m.name.startswith("_")
    )


def run(name: str, args: list[str]) -> int:
    """Run benchmark ``name`` with command-line ``args``; returns its exit status."""
    module = importlib.import_module(f"benchmarks.{name}")
    sys.argv = [f"benchmarks.{name}", *args]
    return int(module.main() or 0)


def main(argv: list[str]) -> int:
    available = names()
    if argv and argv[0] in ("--list", "-l"):
        print("\n".join(available))
        return 0
    if argv:
        if argv[0] not in available:
            print(f"unknown benchmark '{argv[0]}'. Available: {', '.join(available)}", file=sys.stderr)
            return 2
        return run(argv[0], argv[1:])
    status = 0
    for name in available:
        print(f"== {name}", flush=True)
        status |= run(name, [])
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
