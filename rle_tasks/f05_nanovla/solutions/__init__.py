"""Shipped solutions of the family-05 tasks, materialised by ``rle_tasks.core.solutions``.

Each is one ``solution.py`` (the card's artifact):

- ``reference``: ``solutions/reference/recipe.py``, one behaviour-cloning recipe for LIBERO and the
  stand-in (it tells them apart by the demonstrations' view names). On LIBERO its golden quick score
  is 0.0: the two quick episodes of the public order, task 2 from state 12 and task 3 from state 42,
  both fail in the 20-episode run on the 10-task dataset, which succeeds in 3 of 20 (README).

- ``baseline/mean_action``: serves the mean demonstrated action whatever it sees: replays and
  completes every episode, succeeds in none.
- ``baseline/nan_server``: trains like ``mean_action`` and serves NaN actions: every reply refused
  (``protocol.non_finite``), no episode completes, cap ``incomplete``.
- ``baseline/too_large``: ``mean_action`` padded to 2 MiB: refused by the artifact check
  (``f05.solution_too_large``), cap ``replay_failed``.
- ``baseline/over_budget``: training never ends: stopped at 1,920 s (``sandbox.timeout``), cap
  ``replay_failed``.
- ``baseline/reads_eval_states``: training searches the disk for LIBERO's evaluation states; the
  sandbox keeps them out of reach, training fails (``sandbox.exception``), cap ``replay_failed``.

Golden scores: quick mode (``QUICK_EPISODES`` episodes), public development key.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from rle_tasks.core.solutions import Solution, SolutionSet

PAD_TO = 2 << 20
"""Size of the oversized baseline [B] (the card's cap is 1 MiB)."""


def pad_to_two_mib(root: Path) -> None:
    """Append comment lines to ``solution.py`` until it has ``PAD_TO`` bytes."""
    path = root / "solution.py"
    text = path.read_bytes()
    line = b"# " + b"padding " * 15 + b"\n"
    body = text + line * ((PAD_TO - len(text)) // len(line) + 1)
    path.write_bytes(body[:PAD_TO])


_OPEN = SolutionSet(
    package="rle_tasks.f05_nanovla",
    solutions=(
        Solution(
            "reference",
            sha256="3b298342aee73bf69a4ca5183a6acad86ebf06dc385737913f18242e61ee01ec",
            quick_score=0.0,
            files=(("solution.py", "solutions/reference/recipe.py"),),
        ),
        Solution(
            "baseline/mean_action",
            sha256="1ca85b673d14528e43aec49c97a6082587d5fb0c6adf69cac29205339fc88fce",
            quick_score=0.0,
            files=(("solution.py", "solutions/baseline/mean_action.py"),),
        ),
        Solution(
            "baseline/nan_server",
            sha256="fe871cf5dbc1aca07c65e9bb0ced40c910e74b619e1117bf49222bad81b6583f",
            quick_score=0.0,
            files=(("solution.py", "solutions/baseline/nan_server.py"),),
        ),
        Solution(
            "baseline/too_large",
            sha256="fa33cccff5200444af378c33690e364e3e8775d8cb05c3c332012f1ceb0770c5",
            quick_score=0.0,
            base="baseline/mean_action",
            transforms=(pad_to_two_mib,),
        ),
        Solution(
            "baseline/over_budget",
            sha256="f8e983502a6bb3444bdaa170b3eb6ff83cd453ab350babe50abe7879e89475d4",
            quick_score=0.0,
            files=(("solution.py", "solutions/baseline/over_budget.py"),),
            runs_out_s=1920.0,
        ),
        Solution(
            "baseline/reads_eval_states",
            sha256="9c176203f7f1be5ecc56f83baf1795ecf8d826d78932e773b6aba0d3d1e95471",
            quick_score=0.0,
            files=(("solution.py", "solutions/baseline/reads_eval_states.py"),),
        ),
    ),
)
_ROBUST = SolutionSet(
    package="rle_tasks.f05_nanovla",
    solutions=(
        *(dataclasses.replace(s, quick_score=0.5) for s in _OPEN.solutions if s.name == "reference"),
        *(s for s in _OPEN.solutions if s.name in ("baseline/mean_action", "baseline/too_large")),
    ),
)


ROBUST_AUGMENT = 2
"""Perturbed copies of every frame in the robust track's reference (each copy adds about 250 s of
encoding on this machine's two cores to the open recipe's 420 s of training)."""


def with_augmentation(root: Path) -> None:
    """Set the recipe's ``AUGMENT`` to ``ROBUST_AUGMENT`` (the robust track's reference)."""
    path = root / "solution.py"
    text = path.read_text(encoding="utf-8")
    if "\nAUGMENT = 0\n" not in text:
        raise ValueError("the stand-in recipe no longer declares AUGMENT = 0")
    path.write_text(text.replace("\nAUGMENT = 0\n", f"\nAUGMENT = {ROBUST_AUGMENT}\n"), encoding="utf-8")


def _standin_reference(sha256: str, quick_score: float, transforms=()) -> Solution:
    """The stand-in reference recipe on one track (``transforms``: what that track changes)."""
    return Solution(
        "reference",
        sha256=sha256,
        quick_score=quick_score,
        files=(("solution.py", "solutions/reference/recipe.py"),),
        transforms=transforms,
    )


_STANDIN_OPEN = SolutionSet(
    package="rle_tasks.f05_nanovla",
    solutions=(
        _standin_reference(
            "3b298342aee73bf69a4ca5183a6acad86ebf06dc385737913f18242e61ee01ec", 0.5833333333333334
        ),
        *(
            s
            for s in _OPEN.solutions
            if s.name in ("baseline/mean_action", "baseline/nan_server", "baseline/too_large")
        ),
    ),
)
_STANDIN_ROBUST = SolutionSet(
    package="rle_tasks.f05_nanovla",
    solutions=(
        _standin_reference(
            "5dfc742b6e15bba63dcc62956254e24a6da52ef6bb3ab9a7e64316eab151d2ae",
            0.4166666666666667,
            transforms=(with_augmentation,),
        ),
        *(s for s in _OPEN.solutions if s.name == "baseline/mean_action"),
    ),
)
SOLUTIONS = {
    "05-libero-open": _OPEN,
    "05-libero-robust": _ROBUST,
    "05-robotwin-open": _STANDIN_OPEN,
    "05-robotwin-robust": _STANDIN_ROBUST,
}
"""The LIBERO robust track ships the open track's reference unchanged (golden quick 0.5: its first
episode, a paraphrased instruction of task 5, succeeds; the second, another task in task 5's scene,
fails) and the two baselines whose reasons do not depend on the episode set; the stand-in tracks
ship the reference recipe (``solutions/reference/recipe.py``; on the robust track with
``AUGMENT = ROBUST_AUGMENT``) with the baselines whose reasons hold there."""
