"""Shipped solutions of the family-04 tasks, materialised by ``rle_tasks.core.solutions`` (one
``SolutionSet`` per registered task).

- ``reference``: for ``04-dance`` and ``04-fall-getup``, the whole-body QP expert (``expert_tracker.py``)
  distilled by DAgger into an MLP of four observation frames (``distil.py``) with an output low-pass
  (``smooth.py``), with ``solutions/reference/policy_meta_h4.json`` (history 4); for ``04-fight``, the
  model-based tracking prior of the clip (``prior.py``: inverse-dynamics feedforward fitted by a small MLP, feedback gains tuned by
  the cross-entropy method on design seeds), beside one shared ``solutions/reference/policy_meta.json``
  (history 1, the G1's action scale and default pose). Build commands and curves are in the README.
- ``baseline/open_loop``: replays the reference joint angles of the observation as PD targets.
- ``baseline/zero_action``: PD targets at the default pose.
- ``baseline/nan_output``: every output NaN: smoke failure, cap 0.1.
- ``baseline/non_deterministic``: open loop plus fresh noise per call: smoke failure, cap 0.1.
- ``baseline/twelve_million``: 12.1 M parameters: invalid, 0.

The baselines are ONNX graphs generated at materialisation (``baselines.py``). Golden scores: quick
mode (two hidden seeds), public development key.
"""

from __future__ import annotations

from rle_tasks.core.solutions import Solution, SolutionSet

from . import baselines

PACKAGE = "rle_tasks.f04_motion_tracking"
BASELINES = (
    Solution(
        "baseline/open_loop",
        sha256="74e430affe734cd4ed60567d323f8663d74e64a3e421cfcbd2a223e665ecdba0",
        quick_score=0.0,
        transforms=(baselines.open_loop,),
    ),
    Solution(
        "baseline/zero_action",
        sha256="1086af51e06e68ccbf5e55ff35a0f238bc8205be7a2a8da2427d2748cf49b288",
        quick_score=0.0,
        transforms=(baselines.zero_action,),
    ),
    Solution(
        "baseline/nan_output",
        sha256="d58fb995747e9a25b4c6e0933fec227c6499e7198ce36a1fa4569f76526e41e6",
        quick_score=0.0,
        transforms=(baselines.nan_output,),
    ),
    Solution(
        "baseline/non_deterministic",
        sha256="bf73cf9361eabad57f4ba5696c9d9650d00bce91a26ed8f77fa730d6e0071e2e",
        quick_score=0.0,
        transforms=(baselines.non_deterministic,),
    ),
    Solution(
        "baseline/twelve_million",
        sha256="11d3f5a9fbd448248032a7c3222039d2d99dbad7ec6ffbc6f9ed38aeff8989af",
        quick_score=0.0,
        transforms=(baselines.twelve_million,),
    ),
)
"""The baselines are the same graphs for every task; each scores 0 in quick mode on every registered
clip (they fall within about a second)."""


def _task(style: str, sha256: str, quick_score: float, meta: str = "policy_meta.json") -> SolutionSet:
    """The task's solutions; the reference's ``policy_meta.json`` is ``solutions/reference/<meta>``
    (history 1 for the priors, ``policy_meta_h4.json``, history 4, for the distilled students)."""
    reference = Solution(
        "reference",
        sha256=sha256,
        quick_score=quick_score,
        files=((".", f"solutions/reference/{style}"), ("policy_meta.json", f"solutions/reference/{meta}")),
    )
    return SolutionSet(package=PACKAGE, solutions=(reference, *BASELINES))


SOLUTIONS = {
    "04-fall-getup": _task(
        "fall-getup",
        sha256="af4e29fc60e2ed4bab2e06cdf71141c6c47ce9bb081e374101ce2bd7ab670554",
        quick_score=0.326501897692,
        meta="policy_meta_h4.json",
    ),
    "04-fight": _task(
        "fight",
        sha256="aeab9dc27628e2651b7b609107aa8dd6a74acec28daacb45e1c3d8448fce2a3f",
        quick_score=0.01833579881923251,
    ),
    "04-dance": _task(
        "dance",
        sha256="3d7d27a7c02a906178a61c694b27b150fc4f994ea9afd2bdbe60839265fc3bf4",
        quick_score=0.0289311438964,
        meta="policy_meta_h4.json",
    ),
}
"""Task id -> its solutions (the registered tasks)."""
