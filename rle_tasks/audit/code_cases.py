"""Submitted code that faults, hangs, floods, escapes or lies: one case per kind for every task whose
submission holds code the verifier runs in its sandbox (families 07, 08 and 09).

``HOSTILE[name] = (source, expected code, prepend)``: ``source`` is formatted with ``fn`` (the
overridden function) and ``like`` (an expression shaped like its result); ``prepend`` puts it before
the module (import-time faults) instead of after (later definitions win)."""

from __future__ import annotations

from rle_tasks.audit.artifacts import Target, code
from rle_tasks.audit.case import Case

__all__ = ["HOSTILE", "code_cases"]

HOSTILE = {
    "import_crash": ("raise RuntimeError('boom at import')", "sandbox.import_error", True),
    "monkeypatch_verifier": (
        "import rle_tasks.core.report as _r\n_r.Checkpoint.__post_init__ = lambda self: None",
        "sandbox.import_error",
        True,
    ),
    "hang": (
        "def {fn}(*a, **k):\n    import threading\n    threading.Event().wait()",
        "sandbox.timeout",
        False,
    ),
    "busy_loop": ("def {fn}(*a, **k):\n    while True:\n        pass", "sandbox.timeout", False),
    "sleep_past_cap": ("def {fn}(*a, **k):\n    import time\n    time.sleep(3600)", "sandbox.timeout", False),
    "memory_bomb": ("def {fn}(*a, **k):\n    x = bytearray(64 << 30)\n    return x", "sandbox.memory", False),
    "fork_bomb": (
        "def {fn}(*a, **k):\n    import os\n    while True:\n        os.fork()",
        "sandbox.forbidden",
        False,
    ),
    "read_secret": (
        "def {fn}(*a, **k):\n    import os\n    return os.environ['RLE_SECRET']",
        "sandbox.exception",
        False,
    ),
    "read_verifier_files": (
        "def {fn}(*a, **k):\n    return open('/proc/1/environ', 'rb').read().decode()",
        "sandbox.forbidden",
        False,
    ),
    "write_outside": (
        "def {fn}(*a, **k):\n    open('/tmp/rle_planted_reward.json', 'w').write('{{\"reward\": 1}}')",
        "sandbox.forbidden",
        False,
    ),
    "socket": (
        "def {fn}(*a, **k):\n    import socket\n    socket.create_connection(('127.0.0.1', 9))",
        "sandbox.forbidden",
        False,
    ),
    "signal_parent": (
        "def {fn}(*a, **k):\n    import os\n    os.kill(os.getppid(), 9)",
        "sandbox.forbidden",
        False,
    ),
    "segfault": (
        "def {fn}(*a, **k):\n    import os, signal\n    os.kill(os.getpid(), signal.SIGSEGV)",
        "sandbox.crash",
        False,
    ),
    "sys_exit": ("def {fn}(*a, **k):\n    import sys\n    sys.exit(0)", "sandbox.exit", False),
    "os_exit": ("def {fn}(*a, **k):\n    import os\n    os._exit(3)", "sandbox.exit", False),
    "print_megabytes": (
        "def {fn}(*a, **k):\n    import sys\n    sys.stdout.write('x' * (64 << 20))\n    return _orig_{fn}(*a, **k)",
        "sandbox.output_flood",
        False,
    ),
    "huge_reply": (
        "def {fn}(*a, **k):\n    import numpy as np\n    return np.zeros(40_000_000)",
        "sandbox.output_too_large",
        False,
    ),
    "return_nan": (
        "def {fn}(*a, **k):\n    import numpy as np\n    return np.full(np.shape({like}), np.nan)",
        "sandbox.non_finite",
        False,
    ),
    "return_inf": (
        "def {fn}(*a, **k):\n    import numpy as np\n    return np.full(np.shape({like}), np.inf)",
        "sandbox.non_finite",
        False,
    ),
    "return_string": ("def {fn}(*a, **k):\n    return 'not an array'", "sandbox.bad_type", False),
    "wrong_shape": (
        "def {fn}(*a, **k):\n    import numpy as np\n    return np.zeros((np.size({like}) + 1,))",
        "sandbox.bad_shape",
        False,
    ),
    "raise_midway": (
        "_calls = [0]\ndef {fn}(*a, **k):\n    _calls[0] += 1\n    if _calls[0] > 3:\n"
        "        raise ValueError('controller lost track')\n    return _orig_{fn}(*a, **k)",
        "sandbox.exception",
        False,
    ),
}


def code_cases(target: Target, fn: str, like: str, cap: float, names: tuple[str, ...] = ()) -> list[Case]:
    """One case per ``HOSTILE`` entry (those in ``names`` when given): the reference's function ``fn``
    of the submitted module overridden; ``like`` is an expression of its arguments shaped like its
    result."""
    cases = []
    for name, (src, expect, prepend) in HOSTILE.items():
        if names and name not in names:
            continue
        patch = src.format(fn=fn, like=like)
        if name in ("raise_midway", "print_megabytes"):
            patch = f"_orig_{fn} = {fn}\n" + patch
        cases.append(
            Case(
                f"code/{target.task[:2]}_{name}",
                target.task,
                expect,
                code(target, patch, prepend),
                max_score=cap,
                wall_cap_s=120,
            )
        )
    return cases
