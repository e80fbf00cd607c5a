"""Hostile-input-safe loading of a submitted MJCF directory into a validated ``mujoco.MjSpec``.

Pipeline (MuJoCo never opens a file itself):

1. Every file is reached through ``ArtifactReader``: no absolute path, no ``..`` escape, no symlink out of
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
from dataclasses import dataclass, field
from pathlib import Path, PureWindowsPath

import mujoco
from lxml import etree

from rle_design.errors import MjcfError, UnsafeArtifact
from rle_design.mjcf.artifact_files import ArtifactReader, LoadLimits, check_asset, fail

__all__ = ["DEFAULT_LIMITS", "Design", "LoadLimits", "load_design"]

DEFAULT_LIMITS = LoadLimits()

_MESH_DIR_TAGS = frozenset({"mesh", "hfield", "skin", "flexcomp"})
_TEXTURE_DIR_TAGS = frozenset({"texture"})
_PLUGIN_TAGS = frozenset({"extension", "plugin", "instance"})
_LIBXML_TOO_DEEP = ("Excessive depth",)
_LIBXML_TOO_LARGE = ("too long", "huge text", "Resource limit", "too large")
_LIBXML_ENTITY = ("entity", "Entity")


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
            raise fail(
                "mjcf.too_deep", f"element nesting exceeds {limits.max_depth} levels", path=where, el=el
            )
        if count > limits.max_elements:
            raise fail("mjcf.too_large", f"more than {limits.max_elements} elements", path=where, el=el)
        for key, value in el.attrib.items():
            if len(value) > limits.max_attribute_length:
                raise fail(
                    "mjcf.too_large",
                    f"attribute '{key}' has {len(value)} characters, limit {limits.max_attribute_length}",
                    path=where,
                    el=el,
                )
        stack.extend((child, depth + 1) for child in el)


def _inline_includes(
    tree, rel: str, reader: ArtifactReader, origin: dict, seen: set[str], depth: int = 1
) -> None:
    """Replace every ``<include>`` of ``tree`` (file ``rel``) by the children of the included root."""
    for inc in list(tree.getroot().iter("include")):
        if depth > reader.limits.max_include_depth:
            msg = f"includes nested deeper than {reader.limits.max_include_depth} files"
            raise fail("mjcf.too_deep", msg, path=rel, el=inc)
        inc_rel = reader.resolve(inc.get("file", ""), "", (rel, inc))
        if inc_rel in seen:
            raise fail(
                "mjcf.include_repeat", f"file '{inc_rel}' is included more than once", path=rel, el=inc
            )
        seen.add(inc_rel)
        sub = _parse_xml(
            reader.read(inc_rel, reader.limits.max_xml_bytes, (rel, inc)), inc_rel, reader.limits
        )
        for el in sub.getroot().iter():
            origin[el] = inc_rel
        _inline_includes(sub, inc_rel, reader, origin, seen, depth + 1)
        parent = inc.getparent()  # never None: the root is <mujoco>
        index = parent.index(inc)
        parent.remove(inc)
        for offset, child in enumerate(list(sub.getroot())):
            parent.insert(index + offset, child)


def _asset_dirs(root: etree._Element, origin: dict, entry: str, reader: ArtifactReader) -> dict[str, str]:
    dirs = {"meshdir": "", "texturedir": "", "assetdir": ""}
    for comp in root.iter("compiler"):
        for key in dirs:
            value = comp.get(key)
            if value is not None:
                if value.startswith(("/", "\\", "~")) or PureWindowsPath(value).drive:
                    raise fail(
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


def load_design(
    directory: str | os.PathLike, entry: str = "robot.xml", limits: LoadLimits = DEFAULT_LIMITS
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
    reader = ArtifactReader(root, limits)
    entry_rel = reader.resolve(entry, "", (None, None))
    tree = _parse_xml(reader.read(entry_rel, limits.max_xml_bytes, (entry_rel, None)), entry_rel, limits)
    origin: dict = {}
    _inline_includes(tree, entry_rel, reader, origin, {entry_rel})
    top = tree.getroot()
    _check_size(top, origin, entry_rel, limits)
    if not limits.allow_plugins:
        el = next(top.iter(*_PLUGIN_TAGS), None)
        if el is not None:
            raise fail(
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
            rel = reader.resolve(ref, sub, (where, el))
            if el.tag == "model":
                raise fail(
                    "mjcf.forbidden_element",
                    "<model> sub-model assets are not supported by the safe loader; use <include>",
                    path=where,
                    el=el,
                )
            data = reader.read(rel, limits.max_file_bytes, (where, el))
            check_asset(data, rel, el, limits, where)
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
