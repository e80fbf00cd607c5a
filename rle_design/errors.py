"""One error root for the toolkit; messages name the element and the valid alternatives."""

from __future__ import annotations

from collections.abc import Iterable


class RleError(Exception):
    """Root of every error raised on purpose by RLE-Bench.

    Attributes:
        code: Stable machine-readable code (e.g. ``"mjcf.path_escape"``) used in reports.
        path: The file the error is about, relative to the artifact directory when known.
    """

    code: str = "rle.error"

    def __init__(self, message: str, *, code: str | None = None, path: str | None = None) -> None:
        super().__init__(message)
        if code is not None:
            self.code = code
        self.path = path

    @property
    def message(self) -> str:
        return str(self.args[0]) if self.args else ""


class CatalogError(RleError):
    """A catalog file is missing, malformed, or an entry does not exist."""

    code = "catalog.invalid"


class MjcfError(RleError):
    """An MJCF document cannot be parsed, compiled, or violates a contract.

    Attributes:
        element: Tag of the offending element, when known.
        line: 1-based source line of the offending element, when known.
    """

    code = "mjcf.invalid"

    def __init__(
        self,
        message: str,
        *,
        code: str | None = None,
        path: str | None = None,
        element: str | None = None,
        line: int | None = None,
    ) -> None:
        where = []
        if path:
            where.append(path if line is None else f"{path}:{line}")
        elif line is not None:
            where.append(f"line {line}")
        if element:
            where.append(f"<{element}>")
        full = f"{' '.join(where)}: {message}" if where else message
        super().__init__(full, code=code, path=path)
        self.element = element
        self.line = line


class UnsafeArtifact(MjcfError):
    """A submitted file tries to leave its directory, is too large, or is hostile."""

    code = "artifact.unsafe"


def _plural(noun: str) -> str:
    """English plural of an element kind: body -> bodies, mesh -> meshes, site -> sites."""
    if noun.endswith("y") and noun[-2:-1] not in ("a", "e", "o", "u"):
        return noun[:-1] + "ies"
    return noun + ("es" if noun.endswith(("s", "sh", "ch", "x")) else "s")


class MissingElement(RleError):
    """A required named element is absent; the message lists the available names."""

    code = "contract.missing_element"

    def __init__(self, kind: str, name: str, available: Iterable[str] = (), **kw) -> None:
        avail = sorted(a for a in available if a)
        shown = ", ".join(avail[:30]) + (" ..." if len(avail) > 30 else "")
        msg = f"{kind} '{name}' does not exist. Available {_plural(kind)}: {shown or '(none)'}"
        super().__init__(msg, **kw)
        self.kind = kind
        self.name = name
        self.available = avail


class ConfigError(RleError):
    """A configuration (a spec edit, a variation range, a robot entry) is invalid; names the field."""

    code = "config.invalid"
