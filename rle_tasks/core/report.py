"""Verifier report: the only authoritative output of a verification (JSON with a stable key order).

``VerifierReport``, ``Checkpoint`` and ``ErrorEntry`` are frozen; their JSON form is derived from their
fields in declaration order (a checkpoint adds the derived ``credit`` after ``score``). While a
verifier runs, participant faults are collected in a mutable ``Findings``; the declared rubric
(``rle_tasks.core.scoring``) turns findings and measurements into the frozen report.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rle_design.excerpt import withhold

VERIFIER_VERSION = "0.1.0"


def _clean(value: Any) -> Any:
    """JSON-safe copy: numpy scalars/arrays to Python, non-finite floats to strings."""
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v) for v in value]
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return float(f"{value:.12g}")
    return value


def _unit(value: Any) -> float:
    """A score clamped to [0, 1]; non-finite values score 0."""
    value = float(value)
    return min(1.0, max(0.0, value)) if math.isfinite(value) else 0.0


def _as_dict(obj: Any, derived: dict[str, str] | None = None) -> dict[str, Any]:
    """Fields in declaration order; ``derived`` inserts ``{name: after_field}`` properties."""
    out: dict[str, Any] = {}
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
            out[f.name] = [v.to_dict() for v in value]
        else:
            out[f.name] = _clean(value)
        for name, after in (derived or {}).items():
            if after == f.name:
                out[name] = _clean(getattr(obj, name))
    return out


def _from_dict(cls: type, d: dict[str, Any], nested: dict[str, type] | None = None) -> Any:
    """Inverse of ``_as_dict`` for the fields present in ``d`` (unknown keys are ignored)."""
    kwargs = {}
    for f in dataclasses.fields(cls):
        if f.name not in d:
            continue
        value = d[f.name]
        if nested and f.name in nested:
            value = tuple(nested[f.name].from_dict(v) for v in value)
        kwargs[f.name] = value
    return cls(**kwargs)


@dataclass(frozen=True)
class ErrorEntry:
    """A participant fault or validity finding. ``code`` is stable (e.g. ``mjcf.path_escape``)."""

    code: str
    message: str
    path: str | None = None

    def to_dict(self) -> dict[str, Any]:
        return _as_dict(self)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> ErrorEntry:
        return _from_dict(cls, d)


@dataclass(frozen=True)
class Checkpoint:
    """One rubric checkpoint. ``score`` is clamped to [0, 1]; ``credit = weight * score``."""

    id: str
    weight: float
    score: float
    passed: bool
    message: str = ""
    measured: dict[str, Any] = field(default_factory=dict)
    threshold: dict[str, Any] = field(default_factory=dict)
    per_variant: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "score", _unit(self.score))
        object.__setattr__(self, "passed", bool(self.passed))

    @property
    def credit(self) -> float:
        return self.weight * self.score

    def to_dict(self) -> dict[str, Any]:
        return _as_dict(self, {"credit": "score"})

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> Checkpoint:
        return _from_dict(cls, d)


class Findings:
    """Mutable collector of error entries while a verifier runs (the report itself is frozen)."""

    def __init__(self) -> None:
        self.errors: list[ErrorEntry] = []

    def add_error(self, code: str, message: str, path: str | None = None) -> None:
        self.errors.append(ErrorEntry(code, message, path))


@dataclass(frozen=True)
class VerifierReport:
    """Report of DESIGN.md, built once by the rubric (``rle_tasks.core.scoring``) or the guard.

    ``partial``: verified on a reduced evaluation (``--quick``, or a subset the verifier marks
    ``partial`` in its native metrics); the RLE Index takes such a score only when asked to
    (``rle index --allow-partial``) and says so.
    """

    task_id: str
    family: str
    workflow: str
    score: float = 0.0
    valid: bool = False
    cap: float | None = None
    checkpoints: tuple[Checkpoint, ...] = ()
    native_metrics: dict[str, Any] = field(default_factory=dict)
    errors: tuple[ErrorEntry, ...] = ()
    artifact_sha256: str = ""
    secret: str = "public"
    partial: bool = False
    seed_digest: str = ""
    verifier_version: str = VERIFIER_VERSION
    elapsed_s: float = 0.0
    sandbox_layers: dict[str, bool] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "valid", bool(self.valid))
        object.__setattr__(self, "checkpoints", tuple(self.checkpoints))
        object.__setattr__(self, "errors", tuple(self.errors))
        object.__setattr__(self, "elapsed_s", round(float(self.elapsed_s), 3))

    def replace(self, **changes: Any) -> VerifierReport:
        """A copy with ``changes`` applied (the report is frozen)."""
        return dataclasses.replace(self, **changes)

    def checkpoint(self, cid: str) -> Checkpoint:
        for c in self.checkpoints:
            if c.id == cid:
                return c
        raise KeyError(f"checkpoint '{cid}' not in report; have {[c.id for c in self.checkpoints]}")

    def weighted_score(self) -> float:
        return sum(c.credit for c in self.checkpoints)

    def withheld(self) -> VerifierReport:
        """This report with every participant excerpt replaced by ``«withheld»`` (``rle_design.excerpt``):
        the form of a report made with a private secret, where only codes and facts remain."""
        return self.replace(
            errors=tuple(ErrorEntry(e.code, withhold(e.message), e.path) for e in self.errors),
            checkpoints=tuple(
                dataclasses.replace(
                    c,
                    message=withhold(c.message),
                    measured=withhold(c.measured),
                    per_variant=withhold(c.per_variant),
                )
                for c in self.checkpoints
            ),
            native_metrics=withhold(self.native_metrics),
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON form; the score is clamped to [0, 1] (a non-finite score is written as 0)."""
        d = _as_dict(self)
        d["score"] = _clean(_unit(self.score))
        return d

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2, sort_keys=False)

    def write(self, path: str | os.PathLike) -> Path:
        p = Path(path)
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(self.to_json() + "\n")
        return p

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> VerifierReport:
        d = {"family": "", "workflow": "", **d}
        return _from_dict(cls, d, {"checkpoints": Checkpoint, "errors": ErrorEntry})


def artifact_sha256(directory: str | os.PathLike, max_bytes: int = 512 * 1024 * 1024) -> str:
    """Digest over relative paths and contents of regular files (symlinks hashed as their target text)."""
    root = Path(directory)
    h = hashlib.sha256()
    if not root.is_dir():
        return ""
    total = 0
    for p in sorted(root.rglob("*")):
        rel = p.relative_to(root).as_posix()
        if p.is_symlink():
            h.update(f"L {rel} -> {os.readlink(p)}\n".encode())
        elif p.is_file():
            h.update(f"F {rel}\n".encode())
            with p.open("rb") as fh:
                while chunk := fh.read(1 << 20):
                    total += len(chunk)
                    if total > max_bytes:
                        h.update(b"<truncated>")
                        return h.hexdigest()
                    h.update(chunk)
    return h.hexdigest()
