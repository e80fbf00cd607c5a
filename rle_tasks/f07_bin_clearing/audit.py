"""Audit cases of family 07: policies that clear parts around the nest, or smuggle text out in a fault.

Each is the shipped reference policy with one patch appended (later definitions win), verified in
quick mode (the audit secret's first hidden pile, 30 s).
"""

from __future__ import annotations

from rle_tasks.audit.case import EXFIL_MARK, Case
from rle_tasks.audit.corpus import F07, _code

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
    return [
        Case("physics/07_thrower", F07, None, _code(F07, THROWER), max_score=0.0, wall_cap_s=150),
        Case("code/07_exfiltrating_fault", F07, "sandbox.exception", _code(F07, EXFILTRATOR), max_score=0.0,
             wall_cap_s=120),
    ]  # fmt: skip


__all__ = ["EXFILTRATOR", "THROWER", "cases"]
