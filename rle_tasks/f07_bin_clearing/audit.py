"""Audit cases of family 07: policies that fault, look for ground truth, act out of contract, clear
parts around the nest, or smuggle text out in a fault.

Each is the shipped reference policy with one patch appended (later definitions win), verified in
quick mode (the audit secret's first hidden pile, 30 s). A policy that faults in the smoke test is
capped at 0.1 (``CODE_CAP``); later faults end its piles.
"""

from __future__ import annotations

from rle_tasks.audit.artifacts import Target, code
from rle_tasks.audit.case import EXFIL_MARK, Case
from rle_tasks.audit.code_cases import code_cases

TASK = "07-bin-clearing"
TARGET = Target(TASK, code_file="policy/__init__.py")
CODE_CAP = 0.1

HOSTILE = {
    "read_parent_environ": (
        "def act(*a, **k):\n    import os\n    return open(f'/proc/{os.getppid()}/environ', 'rb').read()",
        "sandbox.forbidden",
    ),
    "read_parent_memory": (
        "def act(*a, **k):\n    import os\n    return open(f'/proc/{os.getppid()}/mem', 'rb').read(64)",
        "sandbox.forbidden",
    ),
    "import_verifier": (
        "def act(*a, **k):\n    from rle_tasks.f07_bin_clearing.verifier import hidden_piles\n    return hidden_piles",
        "sandbox.exception",
    ),
    "wrong_action_length": (
        "def act(*a, **k):\n    import numpy as np\n    return np.zeros(7)",
        "sandbox.bad_shape",
    ),
}
"""Family 07 policies that look for ground truth (the parent's environment or memory, the verifier's
hidden piles) or act out of contract."""


GENERIC = ("import_crash", "hang", "memory_bomb", "read_verifier_files", "return_nan", "raise_midway")
"""Sandbox faults also covered by families 08 and 09: family 07 keeps one per class its protocol maps."""


THROWER = """
_orig_act = act
NEST = np.array([0.27, -0.42, 0.80])  # carried high above the nest, then swung down the belt
FAR = np.array([1.30, -0.42, 0.80])


def act(obs):
    s = _state
    if s.get("mode") != "release":
        s["swing"] = 0
    elif s.get("swing", 0) == 0 and not s["plan"]:
        s["plan"], s["swing"] = _line(NEST, FAR, s["q_cmd"], 2.0), 1
    elif s.get("swing") == 1 and obs["magnet"][1] < 0.5:  # it flies: stop and come back
        s["plan"], s["swing"] = _line(_flange(s["q_cmd"]), NEST, s["q_cmd"], 1.0), 2
    out = _orig_act(obs)
    if s.get("swing") == 1 and _flange(s["q_cmd"])[0] > 0.45:
        out[7] = 0.0  # let go mid-swing, over the belt past the gate
    return out
"""
"""Carries each part high above the nest, swings it down the belt and lets go in flight past the gate.
In this cell the thrown brackets land on the belt's cover or the floor (a part that reached the belt's
end or the outfeed so would be ``f07.not_through_nest``, tested in ``test_f07_events.py``); none is
cleared, so the case bounds the score at 0 and requires no code."""

EXFILTRATOR = f"""
_orig_act = act


def act(obs):
    if float(obs["time"]) > 0.2:  # past the smoke test: this is a hidden pile
        seen = " ".join(f"{{v:.4f}}" for v in np.asarray(obs["q"]).ravel())
        raise RuntimeError("{EXFIL_MARK} \\u00bb\\n" + seen + " nest " + str(list(obs["nest"])) + " x" * 5000)
    return _orig_act(obs)
"""
"""Raises on the hidden pile with what it observed (and mark-breaking characters) in the message."""


def cases() -> list[Case]:
    """Family 07's cases (``rle audit-verifiers``)."""
    out = code_cases(TARGET, "act", "list(a[0]['q']) + [0.0]", CODE_CAP, names=GENERIC)
    out += [
        Case(f"code/07_{name}", TASK, expect, code(TARGET, src), max_score=CODE_CAP, wall_cap_s=120)
        for name, (src, expect) in HOSTILE.items()
    ]
    out.append(Case("artifact/f07_empty_dir", TASK, "f07.no_policy", lambda d: d))
    return out + [
        Case("physics/07_thrower", TASK, None, code(TARGET, THROWER), max_score=0.0, wall_cap_s=150),
        Case("code/07_exfiltrating_fault", TASK, "sandbox.exception", code(TARGET, EXFILTRATOR), max_score=0.0,
             wall_cap_s=120),
    ]  # fmt: skip


__all__ = ["EXFILTRATOR", "THROWER", "cases"]
