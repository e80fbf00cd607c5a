"""Participant text in reports: a short, sanitised, marked excerpt, withheld under a private secret.

Whatever submitted code controls (exception messages, return values, stdout, a child's fault reply)
could carry what it learned about a hidden scene out through a report. Such text enters a message
only through ``excerpt``: printable ASCII on one line, at most ``EXCERPT_CHARS`` characters, between
``«`` and ``»`` (which the excerpt itself can never contain). Our own text (codes, our messages,
numbers we measured) is kept as it is. A report made with a private secret replaces every marked
excerpt by ``«withheld»`` (``withhold``): there only the code and the fact remain.
"""

from __future__ import annotations

import re
from typing import Any

EXCERPT_CHARS = 120
"""Longest participant excerpt in a message [characters]: an exception's type and gist, or a refused
path of the sandbox's tripwire, and no more."""
OPEN, CLOSE = "\u00ab", "\u00bb"
WITHHELD = f"{OPEN}withheld{CLOSE}"
_MARKED = re.compile(f"{OPEN}[^{CLOSE}]*{CLOSE}")
_UNPRINTABLE = re.compile(r"[^\x20-\x7e]")
_SPACES = re.compile(r"\s+")


def excerpt(text: Any, limit: int = EXCERPT_CHARS) -> str:
    """``«text»``: participant text made safe for a report (one line, printable ASCII, truncated).

    Args:
        text: Any participant-controlled value; converted with ``str`` (a failing ``__str__`` gives
            the type's name).
        limit: Most characters kept inside the marks.
    """
    try:
        s = text if isinstance(text, str) else str(text)
    except Exception:  # noqa: BLE001 - a participant object whose __str__ raises
        s = f"<{type(text).__name__}>"
    s = _SPACES.sub(" ", _UNPRINTABLE.sub("?", _SPACES.sub(" ", s[: 8 * limit]))).strip()
    if len(s) > limit:
        s = s[: max(limit - 3, 0)] + "..."
    return f"{OPEN}{s}{CLOSE}"


def withhold(value: Any) -> Any:
    """``value`` with every marked excerpt in its strings (nested in dicts, lists, tuples) withheld."""
    if isinstance(value, str):
        return _MARKED.sub(WITHHELD, value) if OPEN in value else value
    if isinstance(value, dict):
        return {withhold(k): withhold(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return type(value)(withhold(v) for v in value)
    return value


__all__ = ["CLOSE", "EXCERPT_CHARS", "OPEN", "WITHHELD", "excerpt", "withhold"]
