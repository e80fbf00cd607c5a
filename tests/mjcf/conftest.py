"""Helpers for the MJCF tests: write a small artifact directory from strings and bytes."""

from collections.abc import Callable
from pathlib import Path

import pytest


@pytest.fixture
def artifact(tmp_path: Path) -> Callable[..., Path]:
    """``artifact(files)`` writes ``{relative path: str | bytes}`` under a fresh directory and returns it."""

    def write(files: dict[str, str | bytes], name: str = "art") -> Path:
        root = tmp_path / name
        root.mkdir(exist_ok=True)
        for rel, content in files.items():
            path = root / rel
            path.parent.mkdir(parents=True, exist_ok=True)
            if isinstance(content, bytes):
                path.write_bytes(content)
            else:
                path.write_text(content)
        return root

    return write
