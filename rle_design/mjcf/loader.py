"""Hostile-input-safe loading of a submitted MJCF directory into a validated ``mujoco.MjSpec``.

Pipeline (MuJoCo never opens a file itself):

1. Every file is reached through ``_Reader``: no absolute path, no ``..`` escape, no symlink out of
   the directory, regular files only, size limits checked with ``stat`` before reading.
2. XML is parsed by a locked-down lxml parser (no DTD, no entity expansion, no network, no huge
   tree); any ``<!DOCTYPE``/``<!ENTITY`` is refused. Depth, element count and attribute length are
   bounded on the tree with every ``<include>`` inlined by us (each file at most once, paths relative
   to the entry's directory, as MuJoCo does).
3. Every attribute whose name starts with ``file`` (``file``, ``fileright`` ... ``fileback``) on any
   element is a file reference: resolved against the entry directory plus ``meshdir`` (mesh, hfield,
   skin, flexcomp) or ``texturedir`` (texture), ``assetdir`` as fall-back (the last ``<compiler>``
   setting wins), validated, read, and its format sniffed: meshes must be the STL/OBJ/MSH they claim
   with at most ``max_mesh_faces`` faces (``mesh.check_mesh_bytes``), PNGs must carry the PNG
   signature and at most ``max_image_pixels`` pixels.
4. MuJoCo receives a copy of the tree with each reference rewritten to an in-memory asset key
   ``rle<i>/<basename>`` (the basename keeps MuJoCo's default asset names) and the directory
   attributes removed, through ``MjSpec.from_string(xml, assets=...)``; afterwards every file field
   of the spec is checked to be one of those keys. Line numbers in MuJoCo's messages are mapped
   back to the submitted file and line.

``<extension>``/``<plugin>`` are refused unless ``LoadLimits.allow_plugins``; ``<model>`` (sub-model
assets) is always refused after its path is validated, because MuJoCo reads it from disk.
"""

from __future__ import annotations

import copy
import os
import posixpath
import re
import stat
import struct
from dataclasses import dataclass, field
from pathlib import Path, PureWindowsPath

import mujoco
from lxml import etree

from rle_design.errors import MjcfError, UnsafeArtifact
from rle_design.mjcf.mesh import check_mesh_bytes

__all__ = ["Design", "LoadLimits", "load_design"]

_MESH_DIR_TAGS = frozenset({"mesh", "hfield", "skin", "flexcomp"})
_TEXTURE_DIR_TAGS = frozenset({"texture"})
_PLUGIN_TAGS = frozenset({"extension", "plugin", "instance"})
_LIBXML_TOO_DEEP = ("Excessive depth",)
_LIBXML_TOO_LARGE = ("too long", "huge text", "Resource limit", "too large")
_LIBXML_ENTITY = ("entity", "Entity")


@dataclass(frozen=True)
class LoadLimits:
    """Resource limits applied to an untrusted MJCF directory.

    Attributes:
        max_xml_bytes: Largest XML file (entry or include) [bytes].
        max_file_bytes: Largest single mesh, texture, height field or skin [bytes].
        max_total_bytes: Sum of all files read from the directory [bytes].
        max_mesh_faces: Most faces in one mesh, read from the file header or bounded by line count.
        max_image_pixels: Most pixels of one PNG texture/height field (width x height from IHDR).
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
    max_depth: int = 64
    max_elements: int = 200_000
    max_attribute_length: int = 1_000_000
    allow_plugins: bool = False


@dataclass(frozen=True)
class Design:
    """A validated MJCF design.

    Attributes:
        root: Resolved artifact directory.
        entry: Entry XML path, relative to ``root`` (POSIX).
        tree: Parsed tree with includes inlined and original attribute values (``sourceline`` kept).
        spec: ``MjSpec`` built from the validated bytes only.
        files: Every file read, relative to ``root``: entry, includes, then assets, in order.
        xml: The XML string handed to MuJoCo (references rewritten to asset keys).
        assets: Asset key -> bytes handed to MuJoCo.
    """

    root: Path
    entry: str
    tree: etree._ElementTree
    spec: mujoco.MjSpec
    files: tuple[str, ...]
    xml: str
    assets: dict[str, bytes] = field(repr=False)
    _origin: dict = field(repr=False, default_factory=dict)
    _line_map: dict = field(repr=False, default_factory=dict)

    def where(self, element: etree._Element) -> tuple[str, int | None]:
        """(file relative to root, source line) of an element of ``tree``."""
        return self._origin.get(element, self.entry), element.sourceline

    def find(self, tag: str, name: str) -> etree._Element | None:
        """First element ``<tag name="name">`` of the inlined tree, or None."""
        for el in self.tree.getroot().iter(tag):
            if el.get("name") == name:
                return el
        return None

    def line_of(self, tag: str, name: str) -> int | None:
        """Source line of ``<tag name="name">`` (in the file given by ``where``), or None."""
        el = self.find(tag, name)
        return None if el is None else el.sourceline

    def fresh_spec(self) -> mujoco.MjSpec:
        """A new ``MjSpec`` from the validated XML and assets (``spec`` may have been edited)."""
        return _spec_from_string(self.xml, self.assets, self._line_map)

    def compile(self) -> mujoco.MjModel:
        """Compile ``spec``; a MuJoCo error becomes ``MjcfError`` code ``mjcf.compile``."""
        try:
            return self.spec.compile()
        except (ValueError, RuntimeError, TypeError) as exc:
            text, (path, line) = _map_lines(str(exc), self._line_map)
            raise MjcfError(
                f"MuJoCo compile error: {text}", code="mjcf.compile", path=path or self.entry, line=line
            ) from None


def _fail(code: str, message: str, *, path: str | None, el=None, unsafe: bool = False) -> MjcfError:
    cls = UnsafeArtifact if unsafe else MjcfError
    tag = el.tag if el is not None and isinstance(el.tag, str) else None
    line = el.sourceline if el is not None else None
    return cls(message, code=code, path=path, element=tag, line=line)


class _Reader:
    """Reads files strictly inside ``root`` within the limits; counts the bytes read."""

    def __init__(self, root: Path, limits: LoadLimits) -> None:
        self.root = root
        self.limits = limits
        self.total = 0
        self.files: list[str] = []

    def resolve(self, ref: str, base: str, *, path: str | None, el=None) -> str:
        """Validate reference ``ref`` (relative to directory ``base`` of root); return root-relative path."""
        shown = f"'{ref}'" if len(ref) < 200 else f"'{ref[:200]}...'"
        if not ref or "\x00" in ref:
            raise _fail("artifact.missing_file", f"empty or invalid file reference {shown}", path=path, el=el)
        if ref.startswith(("/", "\\", "~")) or PureWindowsPath(ref).drive or re.match(r"^[a-zA-Z]+:", ref):
            raise _fail(
                "artifact.path_absolute",
                f"file {shown} is absolute; references must be relative to the artifact directory",
                path=path,
                el=el,
                unsafe=True,
            )
        rel = posixpath.normpath(posixpath.join(base, ref.replace("\\", "/")))
        if rel == ".." or rel.startswith("../"):
            raise _fail(
                "artifact.path_escape",
                f"file {shown} resolves outside the artifact directory",
                path=path,
                el=el,
                unsafe=True,
            )
        try:
            return self._locate(rel, shown, path=path, el=el)
        except OSError as exc:
            raise _fail(
                "artifact.unreadable",
                f"file {shown} cannot be accessed: {exc.strerror or exc}",
                path=path,
                el=el,
                unsafe=True,
            ) from None

    def _locate(self, rel: str, shown: str, *, path: str | None, el) -> str:
        full = self.root / rel
        real = Path(os.path.realpath(full))
        if real != self.root and self.root not in real.parents:
            links = [
                p
                for p in [full, *full.parents]
                if p != self.root and self.root in p.parents and p.is_symlink()
            ]
            if links:
                raise _fail(
                    "artifact.symlink_escape",
                    f"file {shown} goes through symlink '{links[-1].relative_to(self.root).as_posix()}' "
                    "pointing outside the artifact directory",
                    path=path,
                    el=el,
                    unsafe=True,
                )
            raise _fail(
                "artifact.path_escape",
                f"file {shown} resolves outside the artifact directory",
                path=path,
                el=el,
                unsafe=True,
            )
        if not real.exists():
            what = "is a broken or looping symlink" if os.path.lexists(full) else "does not exist"
            raise _fail(
                "artifact.missing_file", f"file {shown} (looked for '{rel}') {what}", path=path, el=el
            )
        if not stat.S_ISREG(real.stat().st_mode):
            raise _fail(
                "artifact.not_a_file", f"file {shown} is not a regular file", path=path, el=el, unsafe=True
            )
        return real.relative_to(self.root).as_posix()

    def read(self, rel: str, limit: int, *, path: str | None, el=None) -> bytes:
        """Read a resolved file, refusing it before reading when larger than ``limit``."""
        try:
            return self._read(rel, limit, path=path, el=el)
        except OSError as exc:
            raise _fail(
                "artifact.unreadable",
                f"file '{rel}' cannot be read: {exc.strerror or exc}",
                path=path,
                el=el,
                unsafe=True,
            ) from None

    def _read(self, rel: str, limit: int, *, path: str | None, el) -> bytes:
        fd = os.open(self.root / rel, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
        try:
            st = os.fstat(fd)
            if not stat.S_ISREG(st.st_mode):
                raise _fail(
                    "artifact.not_a_file",
                    f"file '{rel}' is not a regular file",
                    path=path,
                    el=el,
                    unsafe=True,
                )
            if st.st_size > limit:
                raise _fail(
                    "artifact.too_large",
                    f"file '{rel}' has {st.st_size} bytes, limit {limit}",
                    path=path,
                    el=el,
                    unsafe=True,
                )
            if self.total + st.st_size > self.limits.max_total_bytes:
                raise _fail(
                    "artifact.too_large",
                    f"file '{rel}' brings the files read to {self.total + st.st_size} bytes, "
                    f"limit {self.limits.max_total_bytes}",
                    path=path,
                    el=el,
                    unsafe=True,
                )
            with os.fdopen(fd, "rb", closefd=False) as fh:
                data = fh.read(limit + 1)
        finally:
            os.close(fd)
        if len(data) > limit:
            raise _fail(
                "artifact.too_large", f"file '{rel}' exceeds {limit} bytes", path=path, el=el, unsafe=True
            )
        self.total += len(data)
        self.files.append(rel)
        return data


def _parse_xml(data: bytes, rel: str, limits: LoadLimits) -> etree._ElementTree:
    head = data[:4096]
    if b"<!DOCTYPE" in data or b"<!ENTITY" in head or b"<\x00!\x00D" in head:
        raise MjcfError(
            "DOCTYPE/ENTITY declarations are not allowed in MJCF (entity expansion is disabled)",
            code="mjcf.entity",
            path=rel,
        )
    parser = etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_pis=True,
        collect_ids=False,
    )
    try:
        tree = etree.ElementTree(etree.fromstring(data, parser))
    except etree.XMLSyntaxError as exc:
        line, col = exc.position if exc.position else (exc.lineno, None)
        msg = re.sub(r",? line \d+, column \d+\s*$", "", str(exc.msg or exc)).strip()
        code = "mjcf.parse"
        if any(s in msg for s in _LIBXML_TOO_DEEP):
            code = "mjcf.too_deep"
        elif any(s in msg for s in _LIBXML_TOO_LARGE):
            code = "mjcf.too_large"
        elif any(s in msg for s in _LIBXML_ENTITY):
            code = "mjcf.entity"
        raise MjcfError(
            f"XML parse error at line {line}, column {col}: {msg}", code=code, path=rel, line=line
        ) from None
    except ValueError as exc:  # e.g. lxml refusing an empty document
        raise MjcfError(f"XML parse error: {exc}", code="mjcf.parse", path=rel) from None
    if tree.docinfo.internalDTD is not None or tree.docinfo.doctype:
        raise MjcfError("DOCTYPE/ENTITY declarations are not allowed in MJCF", code="mjcf.entity", path=rel)
    root = tree.getroot()
    if root.tag != "mujoco":
        raise MjcfError(
            f"root element is <{root.tag}>, expected <mujoco>: not an MJCF file",
            code="mjcf.not_mjcf",
            path=rel,
            element=str(root.tag),
            line=root.sourceline,
        )
    return tree


def _check_size(root: etree._Element, origin: dict, entry: str, limits: LoadLimits) -> None:
    count = 0
    stack = [(root, 1)]
    while stack:
        el, depth = stack.pop()
        if not isinstance(el.tag, str):
            continue
        count += 1
        where = origin.get(el, entry)
        if depth > limits.max_depth:
            raise _fail(
                "mjcf.too_deep", f"element nesting exceeds {limits.max_depth} levels", path=where, el=el
            )
        if count > limits.max_elements:
            raise _fail("mjcf.too_large", f"more than {limits.max_elements} elements", path=where, el=el)
        for key, value in el.attrib.items():
            if len(value) > limits.max_attribute_length:
                raise _fail(
                    "mjcf.too_large",
                    f"attribute '{key}' has {len(value)} characters, limit {limits.max_attribute_length}",
                    path=where,
                    el=el,
                )
        stack.extend((child, depth + 1) for child in el)


def _inline_includes(tree, rel: str, reader: _Reader, origin: dict, seen: set[str]) -> None:
    """Replace every ``<include>`` of ``tree`` (file ``rel``) by the children of the included root."""
    for inc in list(tree.getroot().iter("include")):
        inc_rel = reader.resolve(inc.get("file", ""), "", path=rel, el=inc)
        if inc_rel in seen:
            raise _fail(
                "mjcf.include_repeat", f"file '{inc_rel}' is included more than once", path=rel, el=inc
            )
        seen.add(inc_rel)
        sub = _parse_xml(
            reader.read(inc_rel, reader.limits.max_xml_bytes, path=rel, el=inc), inc_rel, reader.limits
        )
        for el in sub.getroot().iter():
            origin[el] = inc_rel
        _inline_includes(sub, inc_rel, reader, origin, seen)
        parent = inc.getparent()
        if parent is None:
            raise _fail("mjcf.not_mjcf", "<include> cannot be the root element", path=rel, el=inc)
        index = parent.index(inc)
        parent.remove(inc)
        for offset, child in enumerate(list(sub.getroot())):
            parent.insert(index + offset, child)


def _asset_dirs(root: etree._Element, origin: dict, entry: str, reader: _Reader) -> dict[str, str]:
    dirs = {"meshdir": "", "texturedir": "", "assetdir": ""}
    for comp in root.iter("compiler"):
        for key in dirs:
            value = comp.get(key)
            if value is not None:
                if value.startswith(("/", "\\", "~")) or PureWindowsPath(value).drive:
                    raise _fail(
                        "artifact.path_absolute",
                        f"{key} '{value}' is absolute; it must be relative to the artifact directory",
                        path=origin.get(comp, entry),
                        el=comp,
                        unsafe=True,
                    )
                dirs[key] = value
    return {
        "mesh": dirs["meshdir"] or dirs["assetdir"],
        "texture": dirs["texturedir"] or dirs["assetdir"],
    }


def _spec_from_string(xml: str, assets: dict[str, bytes], line_map: dict) -> mujoco.MjSpec:
    try:
        spec = mujoco.MjSpec.from_string(xml, assets=dict(assets))
    except (ValueError, RuntimeError, TypeError) as exc:
        text, where = _map_lines(str(exc), line_map)
        raise MjcfError(
            f"MuJoCo parse error: {text}", code="mjcf.schema", path=where[0], line=where[1]
        ) from None
    for group in (spec.meshes, spec.hfields, spec.skins, spec.textures):
        for item in group:
            names = [item.file] + (list(item.cubefiles) if hasattr(item, "cubefiles") else [])
            for name in names:
                if name and name not in assets:
                    raise UnsafeArtifact(
                        f"MuJoCo asset '{item.name}' refers to unvalidated file '{name}'",
                        code="artifact.unvalidated_reference",
                    )
    return spec


def _map_lines(message: str, line_map: dict) -> tuple[str, tuple[str | None, int | None]]:
    """Rewrite MuJoCo's ``line N`` (of the XML we generated) as ``line L of FILE`` (submitted), and
    in-memory asset keys (the ``str`` keys of ``line_map``) as the submitted paths.

    Returns the rewritten message and the (file, line) of the first mapped line, or (None, None).
    """
    first: list = []

    def repl(m: re.Match) -> str:
        where = line_map.get(int(m.group(1)))
        if not where:
            return m.group(0)
        first.append(where)
        return f"line {where[1]} of {where[0]}"

    text = re.sub(r"line (\d+)", repl, message.strip())
    for key, rel in line_map.items():  # in-memory asset keys back to submitted paths
        if isinstance(key, str):
            text = text.replace(f"'{key}'", f"'{rel}'")
    return text, (first[0] if first else (None, None))


def _check_png(data: bytes, max_pixels: int) -> None:
    if data[:8] != b"\x89PNG\r\n\x1a\n" or len(data) < 24 or data[12:16] != b"IHDR":
        raise MjcfError("file is not a PNG image (bad signature)", code="artifact.invalid_format")
    width, height = struct.unpack(">II", data[16:24])
    if width * height > max_pixels:
        raise MjcfError(
            f"PNG is {width} x {height} = {width * height} pixels, limit {max_pixels}",
            code="artifact.too_large",
        )


def _check_asset(data: bytes, rel: str, el, limits: LoadLimits, where: str) -> None:
    suffix = posixpath.splitext(rel)[1].lower()
    ctype = el.get("content_type")
    try:
        if el.tag == "mesh" or (el.tag == "flexcomp" and suffix in (".stl", ".obj")):
            check_mesh_bytes(data, rel, ctype, limits.max_mesh_faces)
        elif suffix == ".png" or ctype == "image/png":
            _check_png(data, limits.max_image_pixels)
    except MjcfError as exc:
        raise _fail(exc.code, f"file '{rel}': {exc.message}", path=where, el=el, unsafe=True) from None


def load_design(
    directory: str | os.PathLike, entry: str = "robot.xml", limits: LoadLimits = LoadLimits()
) -> Design:
    """Load and validate ``directory/entry`` and every file it references.

    Args:
        directory: The artifact directory; nothing outside it is read.
        entry: Entry MJCF file, relative to ``directory``.
        limits: Resource limits.

    Returns:
        The validated ``Design`` (its ``spec`` is parsed, not compiled: call ``compile()``).

    Raises:
        MjcfError: Parse/limit/forbidden-element/schema problems (``mjcf.*``, ``mesh.*`` codes).
        UnsafeArtifact: Path, symlink and size problems (``artifact.*`` codes).
    """
    base = Path(directory)
    if not base.is_dir():
        raise UnsafeArtifact(f"artifact directory '{directory}' does not exist", code="artifact.missing_dir")
    root = Path(os.path.realpath(base))
    reader = _Reader(root, limits)
    entry_rel = reader.resolve(entry, "", path=None)
    tree = _parse_xml(reader.read(entry_rel, limits.max_xml_bytes, path=entry_rel), entry_rel, limits)
    origin: dict = {}
    _inline_includes(tree, entry_rel, reader, origin, {entry_rel})
    top = tree.getroot()
    _check_size(top, origin, entry_rel, limits)
    if not limits.allow_plugins:
        el = next(top.iter(*_PLUGIN_TAGS), None)
        if el is not None:
            raise _fail(
                "mjcf.forbidden_element",
                f"<{el.tag}> is not allowed: engine plugins run native code",
                path=origin.get(el, entry_rel),
                el=el,
            )
    dirs = _asset_dirs(top, origin, entry_rel, reader)
    flat = copy.deepcopy(tree)
    assets: dict[str, bytes] = {}
    key_to_rel: dict[str, str] = {}
    for el, twin in zip(top.iter(), flat.getroot().iter()):
        if not isinstance(el.tag, str):
            continue
        where = origin.get(el, entry_rel)
        if el.tag == "compiler":
            for key in ("meshdir", "texturedir", "assetdir"):
                twin.attrib.pop(key, None)
        for key, ref in el.attrib.items():
            if not key.startswith("file"):
                continue
            sub = (
                dirs["mesh"]
                if el.tag in _MESH_DIR_TAGS
                else dirs["texture"]
                if el.tag in _TEXTURE_DIR_TAGS
                else ""
            )
            rel = reader.resolve(ref, sub, path=where, el=el)
            if el.tag == "model":
                raise _fail(
                    "mjcf.forbidden_element",
                    "<model> sub-model assets are not supported by the safe loader; use <include>",
                    path=where,
                    el=el,
                )
            data = reader.read(rel, limits.max_file_bytes, path=where, el=el)
            _check_asset(data, rel, el, limits, where)
            key_name = f"rle{len(assets)}/{posixpath.basename(rel)}"
            assets[key_name] = data
            key_to_rel[key_name] = rel
            twin.set(key, key_name)
    xml = etree.tostring(flat, encoding="unicode")
    line_map: dict = {
        new.sourceline: (origin.get(old, entry_rel), old.sourceline)
        for old, new in zip(top.iter(), etree.fromstring(xml).iter())
        if new.sourceline is not None
    }
    line_map.update(key_to_rel)
    spec = _spec_from_string(xml, assets, line_map)
    return Design(root, entry_rel, tree, spec, tuple(reader.files), xml, assets, origin, line_map)
