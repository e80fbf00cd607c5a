"""Baseline recipe that must fail: training looks for LIBERO's evaluation initial states on disk.

It searches the installations beside its interpreter for LIBERO-10's ``init_files`` and reads them
to memorise the evaluation scenes. The sandbox confines training to its own directory, the
interpreter's trees and the public toolkit, so the search finds nothing readable (or the read is
refused) and training fails (``sandbox.exception``): no checkpoint, score zero.
"""

import sys
from pathlib import Path


def train(demos_dir: str) -> None:
    roots = [Path(sys.prefix).parent, Path(sys.prefix).parent.parent]
    pattern = "*/lib/python*/site-packages/libero/libero/init_files/libero_10/*.pruned_init*"
    found = [p for r in roots for p in r.glob(pattern)]
    if not found:
        raise FileNotFoundError(f"no LIBERO-10 evaluation states readable under {[str(r) for r in roots]}")
    states = {p.name: p.read_bytes() for p in found}
    with open("ckpt.pt", "wb") as f:
        f.write(b"".join(states.values()))


def serve(socket_path: str) -> int:
    raise RuntimeError("this recipe only memorises evaluation states")
