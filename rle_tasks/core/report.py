"""Verifier report: the only authoritative output of a verification (JSON with a stable key order)."""

from __future__ import annotations

import hashlib
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

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


@dataclass
class ErrorEntry:
    """A participant fault or validity finding. ``code`` is stable (e.g. ``mjcf.path_escape``)."""

    code: str
    message: str
    path: str | None = None

    def to_dict(self) -> dict[str, Any]:
        return {"code": self.code, "message": self.message, "path": self.path}


@dataclass
class Checkpoint:
    """One rubric checkpoint. ``credit = weight * score``."""

    id: str
    weight: float
    score: float
    passed: bool
    message: str = ""
    measured: dict[str, Any] = field(default_factory=dict)
    threshold: dict[str, Any] = field(default_factory=dict)
    per_variant: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not math.isfinite(self.score):
            self.score = 0.0
        self.score = min(1.0, max(0.0, float(self.score)))

    @property
    def credit(self) -> float:
        return self.weight * self.score

    def to_dict(self) -> dict[str, Any]:
        return {
            "id": self.id,
            "weight": _clean(self.weight),
            "score": _clean(self.score),
            "credit": _clean(self.credit),
            "passed": bool(self.passed),
            "message": self.message,
            "measured": _clean(self.measured),
            "threshold": _clean(self.threshold),
            "per_variant": _clean(self.per_variant),
        }


@dataclass
class VerifierReport:
    """Report of DESIGN.md. ``score`` is set by the verifier after caps and deductions."""

    task_id: str
    family: str
    workflow: str
    score: float = 0.0
    valid: bool = False
    cap: float | None = None
    checkpoints: list[Checkpoint] = field(default_factory=list)
    native_metrics: dict[str, Any] = field(default_factory=dict)
    errors: list[ErrorEntry] = field(default_factory=list)
    artifact_sha256: str = ""
    secret: str = "public"
    seed_digest: str = ""
    verifier_version: str = VERIFIER_VERSION
    elapsed_s: float = 0.0

    def add_error(self, code: str, message: str, path: str | None = None) -> None:
        self.errors.append(ErrorEntry(code, message, path))

    def checkpoint(self, cid: str) -> Checkpoint:
        for c in self.checkpoints:
            if c.id == cid:
                return c
        raise KeyError(f"checkpoint '{cid}' not in report; have {[c.id for c in self.checkpoints]}")

    def weighted_score(self) -> float:
        return sum(c.credit for c in self.checkpoints)

    def to_dict(self) -> dict[str, Any]:
        score = self.score if math.isfinite(self.score) else 0.0
        return {
            "task_id": self.task_id,
            "family": self.family,
            "workflow": self.workflow,
            "score": _clean(min(1.0, max(0.0, score))),
            "valid": bool(self.valid),
            "cap": _clean(self.cap),
            "checkpoints": [c.to_dict() for c in self.checkpoints],
            "native_metrics": _clean(self.native_metrics),
            "errors": [e.to_dict() for e in self.errors],
            "artifact_sha256": self.artifact_sha256,
            "secret": self.secret,
            "seed_digest": self.seed_digest,
            "verifier_version": self.verifier_version,
            "elapsed_s": round(float(self.elapsed_s), 3),
        }

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2, sort_keys=False)

    def write(self, path: str | os.PathLike) -> Path:
        p = Path(path)
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(self.to_json() + "\n")
        return p

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> VerifierReport:
        r = cls(task_id=d["task_id"], family=d.get("family", ""), workflow=d.get("workflow", ""))
        r.score = float(d.get("score", 0.0))
        r.valid = bool(d.get("valid", False))
        r.cap = d.get("cap")
        r.checkpoints = [
            Checkpoint(
                c["id"],
                c["weight"],
                c["score"],
                c["passed"],
                c.get("message", ""),
                c.get("measured", {}),
                c.get("threshold", {}),
                c.get("per_variant", {}),
            )
            for c in d.get("checkpoints", [])
        ]
        r.native_metrics = d.get("native_metrics", {})
        r.errors = [ErrorEntry(e["code"], e["message"], e.get("path")) for e in d.get("errors", [])]
        r.artifact_sha256 = d.get("artifact_sha256", "")
        r.secret = d.get("secret", "public")
        r.seed_digest = d.get("seed_digest", "")
        r.verifier_version = d.get("verifier_version", "")
        r.elapsed_s = float(d.get("elapsed_s", 0.0))
        return r


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
