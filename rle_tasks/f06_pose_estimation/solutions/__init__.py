"""Shipped solutions of the ``06-pose-*`` tasks (one ``SolutionSet`` per variant, ``variant_<x>.py``).

B carries every estimator baseline; A and D the reference and one baseline each (the full demo
verifies each shipped solution in full, so the slow ones are not repeated).

- ``reference`` (A, B, D): the classical estimator ``reference/estimator.py`` with ``templates.npz``
  built by ``build_templates.py`` from labelled development renders.
- ``baseline/wrong_shape``: the reference with every shape id shifted by one (each group scores 0).
- ``baseline/nan_output``: returns NaN (interface gate: non-finite output, score 0).
- ``baseline/hang``: ``update`` never returns (interface gate: timeout, score 0).
- ``reference`` (C): ``reference_c/model.pt`` trained by ``python -m rle_tasks.f06_pose_estimation.train``.
- ``baseline/nan_output`` (C): a TorchScript model returning NaN; ``baseline/big_model`` (C): 25 M
  tensor elements, refused before inference (both built by ``make_models.py``).
- ``baseline/slow``: the reference taking ``SLOW_UPDATE_CPU_S`` of CPU per frame (about 2 frames/s: speed
  deduction).
"""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.solutions import Solution

PACKAGE = "rle_tasks.f06_pose_estimation"
REFERENCE_FILES = (
    ("estimator.py", "solutions/reference/estimator.py"),
    ("templates.npz", "solutions/reference/templates.npz"),
)


def solution_names(letter: str) -> tuple[str, ...]:
    """Names of the shipped solutions of variant ``letter``."""
    from importlib import import_module

    sset = import_module(f"{__name__}.variant_{letter}").SOLUTIONS
    return sset.names


def _edit(directory: Path, old: str, new: str) -> None:
    path = directory / "estimator.py"
    text = path.read_text()
    if old not in text:
        raise ValueError(f"{path}: '{old}' not found")
    path.write_text(text.replace(old, new))


def shift_shape(directory: Path) -> None:
    """Return shape id ``(s + 1) % 3`` instead of ``s``."""
    _edit(
        directory,
        "return (float(pose[0]), float(pose[1]), float(t), int(s))",
        "return (float(pose[0]), float(pose[1]), float(t), int((s + 1) % 3))",
    )


SLOW_UPDATE_CPU_S = 0.5
"""CPU time of every ``update`` of ``baseline/slow`` [s], whatever the machine: about 2 frames/s."""


def slow_down(directory: Path) -> None:
    """Wrap ``update`` so that every call takes ``SLOW_UPDATE_CPU_S`` of the process's CPU time: the
    reference's work, then a busy wait on ``time.process_time`` (a fixed amount of CPU, not of
    arithmetic, so the frame rate and the speed deduction do not depend on how fast the CPU is)."""
    path = directory / "estimator.py"
    path.write_text(
        path.read_text()
        + f"""

import time as _time

_reference_update = update
SLOW_UPDATE_CPU_S = {SLOW_UPDATE_CPU_S!r}


def update(obs):
    t0 = _time.process_time()
    out = _reference_update(obs)
    while _time.process_time() - t0 < SLOW_UPDATE_CPU_S:
        pass
    return out
"""
    )


def estimator_solutions(pins: dict[str, tuple[str, float]]) -> tuple[Solution, ...]:
    """Reference and the baselines named in ``pins`` of an estimator variant, with their pins."""
    make = {
        "reference": lambda p: Solution("reference", *p, files=REFERENCE_FILES),
        "baseline/wrong_shape": lambda p: Solution(
            "baseline/wrong_shape", *p, base="reference", transforms=(shift_shape,)
        ),
        "baseline/nan_output": lambda p: Solution(
            "baseline/nan_output", *p, files=(("estimator.py", "solutions/baseline/nan_output/estimator.py"),)
        ),
        "baseline/hang": lambda p: Solution(
            "baseline/hang", *p, files=(("estimator.py", "solutions/baseline/hang/estimator.py"),)
        ),
        "baseline/slow": lambda p: Solution("baseline/slow", *p, base="reference", transforms=(slow_down,)),
    }
    return tuple(make[name](pin) for name, pin in pins.items())


def model_solutions(pins: dict[str, tuple[str, float]]) -> tuple[Solution, ...]:
    """Reference and baselines of the learned variant with their pinned (sha256, quick score)."""
    return (
        Solution("reference", *pins["reference"], files=(("model.pt", "solutions/reference_c/model.pt"),)),
        Solution(
            "baseline/nan_output",
            *pins["baseline/nan_output"],
            files=(("model.pt", "solutions/baseline/nan_model/model.pt"),),
        ),
        Solution(
            "baseline/big_model",
            *pins["baseline/big_model"],
            files=(("model.pt", "solutions/baseline/big_model/model.pt"),),
        ),
    )
