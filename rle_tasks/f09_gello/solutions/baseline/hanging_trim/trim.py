"""Baseline trim whose adaptation never returns (the verifier must time it out and continue)."""

import re
from pathlib import Path

import numpy as np

N_JOINTS = len(re.findall(r"<joint name=", (Path(__file__).resolve().parent / "lead.xml").read_text()))


def plan_probe():
    return np.zeros((15, N_JOINTS))


def feedforward(q, params=None):
    return np.zeros(len(q))


def adapt(probes):
    while True:  # never returns: the verifier's per-call hang cap must end it
        pass
