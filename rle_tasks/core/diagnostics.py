"""Each family's native diagnostics (the paper's appendix): a few labelled numbers per report.

A family declares them with ``diagnostics(report) -> dict[str, float]`` in its ``scoring`` module; the
labels carry their units ("MPJPE [mm]", "survival [%]", "parts/min"). They are what the family
measures in its own terms (08's stage credits over their weights, 09's per-arm rewards, 06's worst-five
errors), never a substitute for the score. A family without the hook shows the top-level numbers of
its reports' native metrics. A report whose metrics the hook cannot read shows nothing: diagnostics
never stop an index from being computed.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable, Mapping
from typing import Any

from rle_tasks.core.report import VerifierReport

BOOKKEEPING = frozenset({"quick", "partial", "secret", "seed_digest", "attempt", "secret_private"})
"""Native keys that say how a report was made, not what was measured: left off the diagnostics."""


def native_scalars(metrics: Mapping[str, Any], limit: int = 24) -> dict[str, Any]:
    """The top-level numbers, flags and short words of a report's native metrics, in report order."""
    out: dict[str, Any] = {}
    for key, value in metrics.items():
        if key in BOOKKEEPING:
            continue
        number = isinstance(value, int | float) and (isinstance(value, bool) or math.isfinite(value))
        if number or (isinstance(value, str) and len(value) <= 24):
            out[key] = value
        if len(out) >= limit:
            break
    return out


def _hook(family: int) -> Callable[[VerifierReport], Mapping[str, Any]] | None:
    from rle_tasks.core.registry import family_packages

    package = family_packages().get(family)
    if package is None:
        return None
    try:
        module = importlib.import_module(f"{package}.scoring")
    except ImportError:
        return None
    return getattr(module, "diagnostics", None)


def task_diagnostics(report: VerifierReport, limit: int = 8) -> dict[str, float]:
    """The family's labelled numbers for one report (finite floats only, in the family's order)."""
    hook = _hook(int(report.task_id.split("-")[0]))
    if hook is None:
        scalars = native_scalars(report.native_metrics)
        values: Mapping[str, Any] = {k: v for k, v in scalars.items() if not isinstance(v, str | bool)}
    else:
        try:
            values = hook(report)
        except (KeyError, TypeError, ValueError, ZeroDivisionError, AttributeError, IndexError):
            return {}
    out: dict[str, float] = {}
    for key, value in values.items():
        if isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value):
            out[str(key)] = float(value)
        if len(out) >= limit:
            break
    return out


def credit_over_weight(report: VerifierReport, groups: Mapping[str, tuple[str, ...]]) -> dict[str, float]:
    """Stage credit divided by stage weight [%] for each named group of checkpoints (the paper's design
    diagnostics: what share of each stage a design earned, before any cap)."""
    by_id = {c.id: c for c in report.checkpoints}
    out: dict[str, float] = {}
    for label, ids in groups.items():
        parts = [by_id[i] for i in ids if i in by_id]
        weight = sum(c.weight for c in parts)
        if weight > 0:
            out[label] = 100.0 * sum(c.credit for c in parts) / weight
    return out


def mean_of(rows: list[Mapping[str, float]]) -> dict[str, float]:
    """Column means over the rows that have each label (the family row of the diagnostics table)."""
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    return {k: sum(r[k] for r in rows if k in r) / sum(1 for r in rows if k in r) for k in keys}
