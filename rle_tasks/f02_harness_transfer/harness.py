"""The submitted harness (``agent_harness/``) and its staging into a fresh agent's workspace: regular
files and directories only, at most ``MAX_FILES`` files and ``MAX_BYTES`` bytes; and the fresh agent's
instruction template."""

from __future__ import annotations

import shutil
from pathlib import Path

__all__ = ["FRESH_INSTRUCTION", "HARNESS_DIR", "MAX_BYTES", "MAX_FILES", "HarnessError", "copy_harness"]

HARNESS_DIR = "agent_harness"
MAX_FILES = 500
MAX_BYTES = 32 << 20
"""Bytes a harness may hold [B] (32 MiB)."""
FRESH_INSTRUCTION = Path(__file__).parent / "assets" / "fresh_instruction.md"
"""A fresh agent's ``instruction.md`` (``str.format`` fields: instruction, steps, minutes)."""


class HarnessError(Exception):
    """The submitted harness cannot be staged (missing, a link, too many files or bytes)."""


def copy_harness(src: Path, dest: Path) -> int:
    """Copy ``src`` (the submitted ``agent_harness/``) to ``dest``: regular files and directories only.

    Returns:
        Files copied.

    Raises:
        HarnessError: ``src`` is missing or a link, holds a link, or more than ``MAX_FILES`` files or
            ``MAX_BYTES`` bytes.
    """
    if src.is_symlink() or not src.is_dir():
        raise HarnessError(f"{HARNESS_DIR}/ is missing or not a directory")
    n = size = 0
    for path in sorted(src.rglob("*")):
        rel = path.relative_to(src)
        if path.is_symlink():
            raise HarnessError(f"{HARNESS_DIR}/{rel} is a symbolic link")
        if "__pycache__" in rel.parts:
            continue
        if path.is_dir():
            (dest / rel).mkdir(parents=True, exist_ok=True)
        elif path.is_file():
            n += 1
            size += path.stat().st_size
            if n > MAX_FILES or size > MAX_BYTES:
                raise HarnessError(
                    f"{HARNESS_DIR}/ holds more than {MAX_FILES} files or {MAX_BYTES >> 20} MiB"
                )
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(path, dest / rel)
    dest.mkdir(parents=True, exist_ok=True)
    return n
