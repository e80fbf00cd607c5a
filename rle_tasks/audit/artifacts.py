"""Builders of hostile artifacts: a shipped reference copied and altered in one place.

A family with a submitted MJCF or submitted code declares a ``Target`` (its task, where the files sit);
the builders here and the generic case lists (``xml_cases``, ``code_cases``) take it, so this package
knows no family.
"""

from __future__ import annotations

import os
import shutil
import struct
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from rle_tasks.core.solutions import materialise

__all__ = [
    "Target",
    "actuator",
    "code",
    "edit_xml",
    "first_body_attr",
    "inject_root",
    "inject_worldbody",
    "inside_first_body",
    "massless",
    "mesh_ref",
    "reference",
    "replace_xml",
    "stl",
    "weld",
    "with_file",
    "with_symlink",
]


@dataclass(frozen=True)
class Target:
    """Where a task's submitted files sit in its reference.

    Attributes:
        task: Task id.
        xml: The submitted MJCF's file name (in each base directory); '' when there is none.
        bases: Sub-directories altered alike (one per leader in family 09); ``("",)``: the root.
        mesh_dir: Where the MJCF's meshes resolve, relative to a base (its ``<compiler meshdir>``).
        code_file: The submitted module the code cases patch, relative to a base.
    """

    task: str
    xml: str = ""
    bases: tuple[str, ...] = ("",)
    mesh_dir: str = ""
    code_file: str = ""

    @property
    def prefix(self) -> str:
        """The family number and a dash (``08-``), the prefix of the generic cases' names."""
        return self.task[:3]

    def base_dirs(self, root: Path) -> list[Path]:
        return [root / b if b else root for b in self.bases]


def reference(task: str, dst: Path) -> Path:
    """Copy the task's shipped reference (materialised and checksum-checked) into ``dst``."""
    shutil.copytree(materialise(task, "reference"), dst, dirs_exist_ok=True, symlinks=True)
    return dst


def edit_xml(target: Target, edit: Callable[[str], str]) -> Callable[[Path], Path]:
    """Copy the reference and apply a text edit to its MJCF (each base's)."""

    def build(d: Path) -> Path:
        reference(target.task, d)
        for base in target.base_dirs(d):
            p = base / target.xml
            p.write_text(edit(p.read_text()))
        return d

    return build


def replace_xml(target: Target, data: bytes | Callable[[bytes], bytes]) -> Callable[[Path], Path]:
    """Copy the reference and replace its MJCF's bytes (or map them)."""

    def build(d: Path) -> Path:
        reference(target.task, d)
        for base in target.base_dirs(d):
            p = base / target.xml
            p.write_bytes(data(p.read_bytes()) if callable(data) else data)
        return d

    return build


def with_file(target: Target, rel: str, data: bytes, edit: Callable[[str], str], sparse: int = 0):
    """``edit_xml``, and a file written where the MJCF's meshes resolve (grown sparse to ``sparse``
    bytes when given)."""

    def build(d: Path) -> Path:
        edit_xml(target, edit)(d)
        for base in target.base_dirs(d):
            f = base / target.mesh_dir / rel
            f.parent.mkdir(parents=True, exist_ok=True)
            f.write_bytes(data)
            if sparse:
                os.truncate(f, sparse)
        return d

    return build


def with_symlink(target: Target, rel: str, to: str, edit: Callable[[str], str]):
    """``edit_xml``, and a symbolic link ``rel`` to ``to`` (among the meshes for an STL)."""

    def build(d: Path) -> Path:
        edit_xml(target, edit)(d)
        for base in target.base_dirs(d):
            ((base / target.mesh_dir if rel.endswith(".stl") else base) / rel).symlink_to(to)
        return d

    return build


def code(target: Target, patch: str, prepend: bool = False) -> Callable[[Path], Path]:
    """Copy the reference and override a function of the submitted module (later definitions win)."""

    def build(d: Path) -> Path:
        reference(target.task, d)
        for base in target.base_dirs(d):
            p = base / target.code_file
            src = p.read_text()
            p.write_text(patch + "\n" + src if prepend else src + "\n\n" + patch + "\n")
        return d

    return build


# ---------------------------------------------------------------- text edits of an MJCF


def inject_worldbody(snippet: str) -> Callable[[str], str]:
    """Insert right after ``<worldbody>``."""
    return lambda xml: xml.replace("<worldbody>", "<worldbody>\n" + snippet, 1)


def inject_root(snippet: str) -> Callable[[str], str]:
    """Insert right after the opening ``<mujoco ...>`` tag."""

    def edit(xml: str) -> str:
        start = xml.index("<mujoco")
        end = xml.index(">", start) + 1
        return xml[:end] + "\n" + snippet + xml[end:]

    return edit


def first_body_attr(attr: str) -> Callable[[str], str]:
    """Add an attribute to the first ``<body ...>`` of the worldbody."""

    def edit(xml: str) -> str:
        i = xml.index("<body", xml.index("<worldbody>"))
        return xml[: i + 5] + f" {attr}" + xml[i + 5 :]

    return edit


def mesh_ref(file: str) -> Callable[[str], str]:
    """Declare a mesh asset from ``file`` and a massive non-colliding geom of it."""
    return lambda xml: inject_root(f'<asset><mesh name="evil" file="{file}"/></asset>')(xml).replace(
        "<worldbody>",
        '<worldbody>\n<geom type="mesh" mesh="evil" contype="0" conaffinity="0" mass="0.001"/>',
        1,
    )


def stl(n_faces: int, tri: tuple = ((0, 0, 0), (1, 0, 0), (0, 1, 0))) -> bytes:
    """A binary STL of ``n_faces`` copies of one triangle."""
    face = struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *v) for v in tri) + b"\0\0"
    return b"\0" * 80 + struct.pack("<I", n_faces) + face * n_faces


def _first_body_name(xml: str) -> str:
    i = xml.index("<body", xml.index("<worldbody>"))
    j = xml.index('name="', i) + 6
    return xml[j : xml.index('"', j)]


def weld(kind: str) -> Callable[[str], str]:
    """An equality constraint (``weld`` or ``connect``) of the first body to the world."""

    def edit(xml: str) -> str:
        body = _first_body_name(xml)
        anchor = ' anchor="0 0 0"' if kind == "connect" else ""
        return xml.replace("</mujoco>", f'<equality><{kind} body1="{body}"{anchor}/></equality>\n</mujoco>')

    return edit


def actuator(xml: str) -> str:
    """A motor on the first joint."""
    i = xml.index("<joint", xml.index("<worldbody>"))
    j = xml.index('name="', i) + 6
    joint = xml[j : xml.index('"', j)]
    return xml.replace("</mujoco>", f'<actuator><motor joint="{joint}" gear="1"/></actuator>\n</mujoco>')


def massless(xml: str) -> str:
    """A moving body with no mass (a hinge with nothing on it): MuJoCo refuses to compile it."""
    i = xml.index("<joint", xml.index("<worldbody>"))
    return (
        xml[:i] + '<body name="ghost" pos="0 0 0.01"><joint name="ghost_j" axis="0 0 1"/></body>\n' + xml[i:]
    )


def inside_first_body(snippet: str) -> Callable[[str], str]:
    """Insert ``snippet`` in the first body, before its first joint."""

    def edit(xml: str) -> str:
        i = xml.index("<joint", xml.index("<worldbody>"))
        return xml[:i] + snippet + "\n" + xml[i:]

    return edit
