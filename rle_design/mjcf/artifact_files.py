"""Reading files of an untrusted artifact directory: path rules, resource limits, format sniffing.

Rules for every file reference (``ArtifactReader.resolve``): not empty, not absolute (``/``, ``~``,
drive letters, URLs: ``artifact.path_absolute``), no ``..`` escape after normalisation
(``artifact.path_escape``), no symlink leading outside the directory (``artifact.symlink_escape``),
must exist (``artifact.missing_file``) and be a regular file (``artifact.not_a_file``: no FIFOs or
devices). ``ArtifactReader.read`` checks sizes with ``fstat`` before reading (``artifact.too_large``)
and never reads more than the limit. ``check_asset`` sniffs asset bytes (meshes through
``mesh.check_mesh_bytes``; PNG signature and pixel count).
"""

from __future__ import annotations

import os
import posixpath
import re
import stat
import struct
from dataclasses import dataclass
from pathlib import Path, PureWindowsPath

from rle_design.errors import MjcfError, UnsafeArtifact
from rle_design.mjcf.mesh import check_mesh_bytes

__all__ = ["ArtifactReader", "LoadLimits", "check_asset", "fail"]


@dataclass(frozen=True)
class LoadLimits:
    """Resource limits applied to an untrusted MJCF directory.

    Attributes:
        max_xml_bytes: Largest XML file (entry or include) [bytes].
        max_file_bytes: Largest single mesh, texture, height field or skin [bytes].
        max_total_bytes: Sum of all files read from the directory [bytes].
        max_mesh_faces: Most faces in one mesh, read from the file header or bounded by line count.
        max_image_pixels: Most pixels of one PNG texture/height field (width x height from IHDR).
        max_files: Most files read (entry, includes and assets).
        max_include_depth: Deepest chain of nested ``<include>`` files.
        max_depth: Deepest element nesting (``<mujoco>`` is depth 1) of the tree with includes inlined.
        max_elements: Most elements in the tree with includes inlined.
        max_attribute_length: Longest attribute value [characters].
        allow_plugins: Accept ``<extension>``/``<plugin>`` elements (engine plugins run native code).
    """

    max_xml_bytes: int = 8 * 2**20
    max_file_bytes: int = 64 * 2**20
    max_total_bytes: int = 256 * 2**20
    max_mesh_faces: int = 2_000_000
    max_image_pixels: int = 4096 * 4096
    max_files: int = 10_000
    max_include_depth: int = 16
    max_depth: int = 64
    max_elements: int = 200_000
    max_attribute_length: int = 1_000_000
    allow_plugins: bool = False


def fail(code: str, message: str, *, path: str | None, el=None, unsafe: bool = False) -> MjcfError:
    """``MjcfError`` (``UnsafeArtifact`` when ``unsafe``) naming file ``path`` and element ``el``'s tag and line."""
    cls = UnsafeArtifact if unsafe else MjcfError
    tag = el.tag if el is not None and isinstance(el.tag, str) else None
    line = el.sourceline if el is not None else None
    return cls(message, code=code, path=path, element=tag, line=line)


def _unsafe(code: str, message: str, ctx: tuple) -> UnsafeArtifact:
    """``UnsafeArtifact`` about the element ``ctx[1]`` of file ``ctx[0]`` (either may be None)."""
    return fail(code, message, path=ctx[0], el=ctx[1], unsafe=True)


class ArtifactReader:
    """Reads files strictly inside ``root`` within the limits; counts the bytes read.

    ``ctx`` arguments are ``(file, element)`` of the reference, used in error messages.
    """

    def __init__(self, root: Path, limits: LoadLimits) -> None:
        self.root = root
        self.limits = limits
        self.total = 0
        self.files: list[str] = []

    def resolve(self, ref: str, base: str, ctx: tuple) -> str:
        """Validate reference ``ref`` (relative to directory ``base`` of root); return root-relative path."""
        shown = f"'{ref}'" if len(ref) < 200 else f"'{ref[:200]}...'"
        if not ref or "\x00" in ref:
            raise fail(
                "artifact.missing_file", f"empty or invalid file reference {shown}", path=ctx[0], el=ctx[1]
            )
        if ref.startswith(("/", "\\", "~")) or PureWindowsPath(ref).drive or re.match(r"^[a-zA-Z]+:", ref):
            msg = f"file {shown} is absolute; references must be relative to the artifact directory"
            raise _unsafe("artifact.path_absolute", msg, ctx)
        rel = posixpath.normpath(posixpath.join(base, ref.replace("\\", "/")))
        if rel == ".." or rel.startswith("../"):
            raise _unsafe(
                "artifact.path_escape", f"file {shown} resolves outside the artifact directory", ctx
            )
        try:
            return self._locate(rel, shown, ctx)
        except OSError as exc:
            raise _unsafe(
                "artifact.unreadable", f"file {shown} cannot be accessed: {exc.strerror or exc}", ctx
            ) from None

    def _locate(self, rel: str, shown: str, ctx: tuple) -> str:
        full = self.root / rel
        real = Path(os.path.realpath(full))
        if real != self.root and self.root not in real.parents:
            links = [p for p in [full, *full.parents] if self.root in p.parents and p.is_symlink()]
            if links:
                link = links[-1].relative_to(self.root).as_posix()
                msg = f"file {shown} goes through symlink '{link}' pointing outside the artifact directory"
                raise _unsafe("artifact.symlink_escape", msg, ctx)
            raise _unsafe(
                "artifact.path_escape", f"file {shown} resolves outside the artifact directory", ctx
            )
        if not real.exists():
            what = "is a broken or looping symlink" if os.path.lexists(full) else "does not exist"
            raise fail(
                "artifact.missing_file", f"file {shown} (looked for '{rel}') {what}", path=ctx[0], el=ctx[1]
            )
        if not stat.S_ISREG(real.stat().st_mode):
            raise _unsafe("artifact.not_a_file", f"file {shown} is not a regular file", ctx)
        return real.relative_to(self.root).as_posix()

    def read(self, rel: str, limit: int, ctx: tuple) -> bytes:
        """Read a resolved file, refusing it before reading when larger than ``limit`` [bytes]."""
        try:
            fd = os.open(self.root / rel, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
            try:
                size = os.fstat(fd).st_size
                if not stat.S_ISREG(os.fstat(fd).st_mode):
                    raise _unsafe("artifact.not_a_file", f"file '{rel}' is not a regular file", ctx)
                if len(self.files) >= self.limits.max_files:
                    raise _unsafe("artifact.too_large", f"more than {self.limits.max_files} files", ctx)
                if size > limit:
                    raise _unsafe("artifact.too_large", f"file '{rel}' has {size} bytes, limit {limit}", ctx)
                if self.total + size > self.limits.max_total_bytes:
                    msg = (
                        f"file '{rel}' brings the files read to {self.total + size} bytes, "
                        f"limit {self.limits.max_total_bytes}"
                    )
                    raise _unsafe("artifact.too_large", msg, ctx)
                with os.fdopen(fd, "rb", closefd=False) as fh:
                    data = fh.read(limit + 1)
            finally:
                os.close(fd)
        except OSError as exc:
            raise _unsafe(
                "artifact.unreadable", f"file '{rel}' cannot be read: {exc.strerror or exc}", ctx
            ) from None
        if len(data) > limit:
            raise _unsafe("artifact.too_large", f"file '{rel}' exceeds {limit} bytes", ctx)
        self.total += len(data)
        self.files.append(rel)
        return data


def _check_png(data: bytes, max_pixels: int) -> None:
    if data[:8] != b"\x89PNG\r\n\x1a\n" or len(data) < 24 or data[12:16] != b"IHDR":
        raise MjcfError("file is not a PNG image (bad signature)", code="artifact.invalid_format")
    width, height = struct.unpack(">II", data[16:24])
    if width * height > max_pixels:
        raise MjcfError(
            f"PNG is {width} x {height} = {width * height} pixels, limit {max_pixels}",
            code="artifact.too_large",
        )


def check_asset(data: bytes, rel: str, el, limits: LoadLimits, where: str) -> None:
    """Sniff the bytes of asset ``rel`` referenced by element ``el`` of file ``where``."""
    suffix = posixpath.splitext(rel)[1].lower()
    ctype = el.get("content_type")
    try:
        if el.tag == "mesh" or (el.tag == "flexcomp" and suffix in (".stl", ".obj")):
            check_mesh_bytes(data, rel, ctype, limits.max_mesh_faces)
        elif suffix == ".png" or ctype == "image/png":
            _check_png(data, limits.max_image_pixels)
    except MjcfError as exc:
        raise fail(exc.code, f"file '{rel}': {exc.message}", path=where, el=el, unsafe=True) from None
