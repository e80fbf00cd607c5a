"""Baseline of ``03-hidden-com``: the reference's probing, but it dawdles after its first answer.

It answers box 0 as the reference does, then holds still for ``IDLE`` steps before probing boxes 1
and 2: their answers come more than 12,000 charged steps after the previous accepted one, so the
environment refuses both as late. Expected: 1/3 (box 0 right), the report naming two late answers.
"""

from __future__ import annotations

from typing import Any

from .reference import Prober, probe_and_answer

IDLE = 12_000
"""Steps held still after the first answer: alone a whole box's budget."""


def solve(env: Any) -> tuple[str, ...]:
    """Probe and answer the three boxes, idling ``IDLE`` steps after the first; returns the answers."""
    prober = Prober(env)
    answers = [probe_and_answer(prober, 0)]
    prober.helper.wait(IDLE)
    answers += [probe_and_answer(prober, box) for box in (1, 2)]
    return tuple(answers)
