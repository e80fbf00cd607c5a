"""Secret handling and HMAC-derived hidden seeds.

Hidden scenes, seeds and device copies derive from HMAC-SHA256(secret, task_id | index). Without a
secret the public development key is used and reports say ``"secret": "public"``.

A development session belongs to one attempt (an id the operator issues: a Harbor trial id, or
``rle dev --attempt``). ``Secret.for_attempt(a)`` mixes the attempt into every derivation
(HMAC(secret, task_id | attempt=a | index)), so the hidden scenes of a session depend on its attempt
and a second attempt learns nothing reusable from a first; the empty attempt derives as before. The
ledger key never depends on the attempt: a ledger of another attempt is refused by name
(``ledger.wrong_attempt``), not as a forgery. ``rle dev`` serves its environment under
``using_secret(secret.for_attempt(a))``, and families read it with ``current_secret()``.
"""

from __future__ import annotations

import hashlib
import hmac
import os
import re
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from rle_design.errors import RleError

PUBLIC_KEY = b"rle-bench public development key v1"
SECRET_ENV = "RLE_SECRET"
ATTEMPT_ENV = "RLE_ATTEMPT"
"""The attempt id when ``--attempt`` is not given (``rle dev``, ``rle verify``)."""
ATTEMPT_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,127}")
"""What an attempt id may be: letters, digits, '.', '_', '-' (a file name), at most 128 characters."""


@dataclass(frozen=True)
class Secret:
    """Key material; ``repr`` never shows the key."""

    key: bytes
    public: bool
    attempt: str = ""

    def __repr__(self) -> str:
        at = f", attempt={self.attempt!r}" if self.attempt else ""
        return f"Secret({'public' if self.public else 'private'}{at})"

    def for_attempt(self, attempt: str) -> Secret:
        """The same key with hidden derivations bound to ``attempt`` ("" unbinds)."""
        if attempt and not ATTEMPT_PATTERN.fullmatch(attempt):
            raise RleError(
                f"attempt id {attempt!r} must be 1-128 letters, digits, '.', '_' or '-', starting with a "
                "letter or digit",
                code="attempt.invalid",
            )
        return replace(self, attempt=attempt)

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
    at = f"attempt={secret.attempt}|" if secret.attempt else ""
    return hmac.new(secret.key, f"{task_id}|{at}{label}".encode(), hashlib.sha256).digest()


_CURRENT: ContextVar[Secret | None] = ContextVar("rle_current_secret", default=None)


@contextmanager
def using_secret(secret: Secret) -> Iterator[Secret]:
    """Make ``secret`` (an attempt's) what ``current_secret()`` returns inside the block."""
    token = _CURRENT.set(secret)
    try:
        yield secret
    finally:
        _CURRENT.reset(token)


def current_secret() -> Secret:
    """The secret of the session being served (``using_secret``), else ``load_secret()``."""
    secret = _CURRENT.get()
    return secret if secret is not None else load_secret()


def derive_seed(secret: Secret, task_id: str, index: int | str) -> int:
    """63-bit seed for hidden item ``index`` of ``task_id``."""
    return int.from_bytes(_mac(secret, task_id, str(index))[:8], "big") >> 1


def derive_rng(secret: Secret, task_id: str, index: int | str) -> np.random.Generator:
    """A numpy Generator for hidden item ``index`` of ``task_id``."""
    return np.random.default_rng(derive_seed(secret, task_id, index))


def seed_digest(secret: Secret, task_id: str) -> str:
    """Public digest identifying the hidden set without revealing it (16 hex chars)."""
    return hashlib.sha256(_mac(secret, task_id, "digest")).hexdigest()[:16]
