"""Earlier trainings of a recipe, for the demo: this machine's cache, and the shipped checkpoints.

A verification trains the submitted recipe (``verifier.verify``). ``rle demo`` (``reuse_training``)
may instead take the checkpoint an earlier training of the same recipe bytes on the same dataset wrote,
under the same training limit and torch version:

* **reused**: this machine's cache (``cache_root()/f05-training/<key>``), written by every training;
* **shipped**: the references' checkpoints in ``checkpoints/`` (``manifest.json`` pins each by its
  recipe's and dataset's sha256, the torch version and the limit, and by its own sha256), so a fresh
  clone's demo evaluates them without hours of training. ``rle demo --full`` retrains and reports
  ``ckpt_reproduced``: whether the retrained checkpoint is byte-identical to the earlier one.

An agent's verification never reuses anything: ``VerifyContext.reuse_training`` is False there.
``python -m rle_tasks.f05_nanovla.pin TASK...`` copies this machine's cached trainings of the
tasks' references into ``checkpoints/`` (after ``rle demo --full --task TASK`` trained them).
"""

from __future__ import annotations

import hashlib
import json
import shutil
import tempfile
from importlib.metadata import version
from pathlib import Path

TRAINING_CACHE_VERSION = 1
SHIPPED = Path(__file__).with_name("checkpoints")
"""The shipped checkpoints and their ``manifest.json``."""


def train_limit() -> float:
    from rle_tasks.envs.libero import replay

    return replay.TRAIN_BUDGET_S


def digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def cache_entry(solution: bytes, dataset_sha256: str) -> Path:
    """This machine's cache entry of a training of ``solution`` on the dataset of that digest: keyed by
    both, the training limit and the installed torch, under ``cache_root()/f05-training``."""
    from rle_tasks.core.solutions import cache_root

    key = hashlib.sha256()
    for part in (
        f"v{TRAINING_CACHE_VERSION}".encode(),
        hashlib.sha256(solution).digest(),
        dataset_sha256.encode(),
        repr(train_limit()).encode(),
        version("torch").encode(),
    ):
        key.update(len(part).to_bytes(4, "big") + part)
    return cache_root() / "f05-training" / key.hexdigest()[:32]


def cached_training(entry: Path) -> tuple[bytes, bytes | None, float] | None:
    """(checkpoint, meta, training seconds) of a complete cache entry, else None."""
    try:
        info = json.loads((entry / "training.json").read_text())
        ckpt = (entry / "ckpt.pt").read_bytes()
        meta = (entry / "meta.json").read_bytes() if (entry / "meta.json").is_file() else None
    except (OSError, ValueError):
        return None
    if digest(ckpt) != info.get("ckpt_sha256"):
        return None
    return ckpt, meta, float(info.get("train_s", 0.0))


def manifest() -> dict[str, dict]:
    """The shipped checkpoints' manifest (``{name: entry}``), empty when there is none."""
    try:
        data = json.loads((SHIPPED / "manifest.json").read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def shipped(solution: bytes, dataset_sha256: str) -> tuple[bytes, bytes | None, float] | None:
    """The shipped checkpoint of a training of ``solution`` on that dataset under this limit and torch,
    checked against its pinned sha256; None when nothing shipped matches."""
    want = {
        "solution_sha256": digest(solution),
        "dataset_sha256": dataset_sha256,
        "torch": version("torch"),
        "train_limit_s": train_limit(),
    }
    for name, entry in manifest().items():
        if not isinstance(entry, dict) or any(entry.get(k) != v for k, v in want.items()):
            continue
        try:
            ckpt = (SHIPPED / f"{name}.pt").read_bytes()
            meta = (SHIPPED / f"{name}.meta.json").read_bytes() if entry.get("meta_sha256") else None
        except OSError:
            return None
        if digest(ckpt) != entry.get("ckpt_sha256") or (
            meta is not None and digest(meta) != entry["meta_sha256"]
        ):
            return None
        return ckpt, meta, float(entry.get("train_s", 0.0))
    return None


def earlier(solution: bytes, dataset_sha256: str) -> tuple[bytes, bytes | None, float, str] | None:
    """(checkpoint, meta, training seconds, "reused" or "shipped") of an earlier training, else None."""
    found = cached_training(cache_entry(solution, dataset_sha256))
    if found is not None:
        return (*found, "reused")
    found = shipped(solution, dataset_sha256)
    return None if found is None else (*found, "shipped")


def store(solution: bytes, dataset_sha256: str, ckpt: bytes, meta: bytes | None, train_s: float) -> None:
    """Write the cache entry atomically (a temporary directory renamed into place); a failure is
    ignored: the cache only saves time."""
    entry = cache_entry(solution, dataset_sha256)
    tmp = None
    try:
        entry.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=".tmp-", dir=entry.parent))
        (tmp / "ckpt.pt").write_bytes(ckpt)
        if meta is not None:
            (tmp / "meta.json").write_bytes(meta)
        (tmp / "training.json").write_text(
            json.dumps({"ckpt_sha256": digest(ckpt), "train_s": train_s}) + "\n"
        )
        shutil.rmtree(entry, ignore_errors=True)
        tmp.rename(entry)
    except OSError:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
