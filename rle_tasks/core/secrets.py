"""Secret handling and HMAC-derived hidden seeds.

Hidden scenes, seeds and device copies derive from HMAC-SHA256(secret, task_id | index). Without a
secret the public development key is used and reports say ``"secret": "public"``.
"""

from __future__ import annotations

import hashlib
import hmac
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rle_design.errors import RleError

PUBLIC_KEY = b"rle-bench public development key v1"
SECRET_ENV = "RLE_SECRET"


@dataclass(frozen=True)
class Secret:
    """Key material; ``repr`` never shows the key."""

    key: bytes
    public: bool

    def __repr__(self) -> str:
        return f"Secret({'public' if self.public else 'private'})"

    @property
    def label(self) -> str:
        return "public" if self.public else "private"


def load_secret(secret_file: str | os.PathLike | None = None) -> Secret:
    """Secret from ``--secret-file``, else ``RLE_SECRET``, else the public development key."""
    if secret_file is not None:
        try:
            key = Path(secret_file).read_bytes().strip()
        except OSError as exc:
            raise RleError(
                f"cannot read secret file {secret_file}: {exc.strerror}", code="secret.unreadable"
            ) from None
        if not key:
            raise RleError(f"secret file {secret_file} is empty", code="secret.empty")
        return Secret(key, public=False)
    env = os.environ.get(SECRET_ENV)
    if env:
        return Secret(env.encode(), public=False)
    return Secret(PUBLIC_KEY, public=True)


def _mac(secret: Secret, task_id: str, label: str) -> bytes:
    return hmac.new(secret.key, f"{task_id}|{label}".encode(), hashlib.sha256).digest()


def derive_seed(secret: Secret, task_id: str, index: int | str) -> int:
    """63-bit seed for hidden item ``index`` of ``task_id``."""
    return int.from_bytes(_mac(secret, task_id, str(index))[:8], "big") >> 1


def derive_rng(secret: Secret, task_id: str, index: int | str) -> np.random.Generator:
    """A numpy Generator for hidden item ``index`` of ``task_id``."""
    return np.random.default_rng(derive_seed(secret, task_id, index))


def seed_digest(secret: Secret, task_id: str) -> str:
    """Public digest identifying the hidden set without revealing it (16 hex chars)."""
    return hashlib.sha256(_mac(secret, task_id, "digest")).hexdigest()[:16]
