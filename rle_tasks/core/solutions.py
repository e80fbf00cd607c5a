"""Shipped solutions, declared once per family and materialised on demand.

A family declares its solutions in ``rle_tasks/<family>/solutions/__init__.py`` as ``SOLUTIONS``, a
``SolutionSet`` (or a dict task id -> ``SolutionSet`` when one module serves several tasks): the reference is a list of committed files, and each baseline names the solution it
starts from and only what differs: an overlay of files (replaced or added) and named transforms
(module-level functions that edit the materialised copy, e.g. an lxml edit of one MJCF attribute).
Every solution pins the ``artifact_sha256`` of its materialised directory and its golden score.

``materialise(task, name)`` builds the directory into a cache outside the repository (``RLE_CACHE_DIR``,
else ``$XDG_CACHE_HOME/rle-bench``, else ``~/.cache/rle-bench``; a temporary directory when none is
writable), keyed by the pinned checksum, and checks the checksum on every call: a mismatch raises
``RleError`` (code ``solutions.checksum``). Nothing is ever written into the package tree.

Golden scores (``Solution.quick_score``) are the verifier's score in quick mode
(``VerifyContext(quick=True)``) under the public development key; ``tests/core/test_solutions.py``
and the family tests check them. After regenerating a solution, ``python -m rle_tasks.core.solutions``
prints the checksums to pin.
"""

from __future__ import annotations

import importlib
import importlib.resources
import os
import shutil
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from importlib.resources.abc import Traversable
from pathlib import Path, PurePosixPath
from typing import TYPE_CHECKING

from lxml import etree

from rle_design.errors import RleError
from rle_tasks.core.report import artifact_sha256

if TYPE_CHECKING:
    from rle_tasks.core.task import TaskSpec

CACHE_ENV = "RLE_CACHE_DIR"
DECLARATION = "SOLUTIONS"
"""Name of the ``SolutionSet`` in a family's solutions package."""
_SKIP = ("__pycache__", ".pyc")

Transform = Callable[[Path], None]
"""Edits a materialised solution directory in place."""


@dataclass(frozen=True)
class Solution:
    """One shipped solution.

    Attributes:
        name: ``"reference"`` or ``"baseline/<name>"``.
        sha256: Pinned ``artifact_sha256`` of the materialised directory.
        quick_score: Golden score: quick mode, public development key.
        base: Solution materialised first (None: an empty directory).
        files: Overlay ``(destination, source)``: destination relative to the solution directory
            (``"."`` for its root), source relative to the family package; a source directory is
            copied recursively (``__pycache__`` and ``.pyc`` left out), files are replaced.
        transforms: Module-level functions applied in order after the overlay.
        runs_out_s: The solution exists to run out a time limit of this many seconds [s] (None: it
            does not): ``rle demo`` lists it with the limit and runs it only with ``--full``.
    """

    name: str
    sha256: str
    quick_score: float
    base: str | None = None
    files: tuple[tuple[str, str], ...] = ()
    transforms: tuple[Transform, ...] = ()
    runs_out_s: float | None = None


@dataclass(frozen=True)
class SolutionSet:
    """A family's declaration of its shipped solutions.

    Attributes:
        package: Dotted name of the family package; overlay sources are relative to it.
        solutions: Reference first, then the baselines.
    """

    package: str
    solutions: tuple[Solution, ...]

    def __post_init__(self) -> None:
        seen: set[str] = set()
        for s in self.solutions:
            if s.name in seen:
                raise RleError(f"solution '{s.name}' is declared twice", code="solutions.invalid")
            if s.base is not None and s.base not in seen:
                raise RleError(
                    f"solution '{s.name}' starts from '{s.base}', which is not declared before it. "
                    f"Declared: {', '.join(sorted(seen)) or '(none)'}",
                    code="solutions.invalid",
                )
            for dest, src in s.files:
                for rel in (dest, src):
                    p = PurePosixPath(rel)
                    if p.is_absolute() or ".." in p.parts:
                        raise RleError(
                            f"solution '{s.name}': path '{rel}' must be relative, without '..'",
                            code="solutions.invalid",
                        )
            for fn in s.transforms:
                module = sys.modules.get(getattr(fn, "__module__", ""))
                if getattr(module, getattr(fn, "__name__", "<none>"), None) is not fn:
                    raise RleError(
                        f"solution '{s.name}': transform {fn!r} must be a module-level function",
                        code="solutions.invalid",
                    )
            seen.add(s.name)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.solutions)

    def get(self, name: str) -> Solution:
        """The solution called ``name``; RleError listing the declared names otherwise."""
        for s in self.solutions:
            if s.name == name:
                return s
        raise RleError(
            f"solution '{name}' is not declared in {self.package}. Declared: {', '.join(self.names)}",
            code="solutions.unknown",
        )


def declaration(task: TaskSpec) -> SolutionSet:
    """Import the ``SolutionSet`` of a task's family (``TaskSpec.solutions_module``)."""
    if not task.solutions_module:
        raise RleError(f"task '{task.id}' ships no solutions", code="solutions.none")
    try:
        module = importlib.import_module(task.solutions_module)
    except ImportError as exc:
        raise RleError(
            f"solutions of task '{task.id}' are not installed ({task.solutions_module}: {exc})",
            code="solutions.missing",
        ) from None
    sset = getattr(module, DECLARATION, None)
    if isinstance(sset, dict):  # one module declaring the sets of several tasks, by task id
        sset = sset.get(task.id)
    if not isinstance(sset, SolutionSet):
        raise RleError(
            f"{task.solutions_module} has no SolutionSet '{DECLARATION}'", code="solutions.invalid"
        )
    return sset


def _task(task_or_id: TaskSpec | str) -> TaskSpec:
    if isinstance(task_or_id, str):
        from rle_tasks.core.registry import get_task

        return get_task(task_or_id)
    return task_or_id


def _copy(src: Traversable, dest: Path) -> None:
    if src.is_dir():
        dest.mkdir(parents=True, exist_ok=True)
        for child in src.iterdir():
            if not child.name.endswith(_SKIP):
                _copy(child, dest / child.name)
    elif src.is_file():
        dest.parent.mkdir(parents=True, exist_ok=True)
        dest.write_bytes(src.read_bytes())
    else:
        raise RleError(f"solution source {src} does not exist", code="solutions.missing_source")


def build(sset: SolutionSet, name: str, dest: Path) -> None:
    """Write solution ``name`` into ``dest`` (created; no checksum check)."""
    sol = sset.get(name)
    if sol.base is not None:
        build(sset, sol.base, dest)
    dest.mkdir(parents=True, exist_ok=True)
    root = importlib.resources.files(sset.package)
    for rel_dest, rel_src in sol.files:
        _copy(root.joinpath(*PurePosixPath(rel_src).parts), dest.joinpath(*PurePosixPath(rel_dest).parts))
    for fn in sol.transforms:
        fn(dest)


def cache_root() -> Path:
    """Directory of materialised solutions (see the module docstring)."""
    env = os.environ.get(CACHE_ENV)
    if env:
        return Path(env)
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "rle-bench"


def _writable_root() -> Path:
    root = cache_root() / "solutions"
    try:
        root.mkdir(parents=True, exist_ok=True)
        probe = tempfile.mkdtemp(dir=root)
        os.rmdir(probe)
        return root
    except OSError:
        root = Path(tempfile.gettempdir()) / f"rle-bench-solutions-{os.getuid()}"
        root.mkdir(parents=True, exist_ok=True)
        return root


def _check(task_id: str, sol: Solution, directory: Path) -> None:
    got = artifact_sha256(directory)
    if got != sol.sha256:
        raise RleError(
            f"materialised solution '{sol.name}' of task '{task_id}' has checksum {got}, but {sol.sha256} "
            "is pinned: its sources or transforms changed. Regenerate it and pin the new checksum "
            "(python -m rle_tasks.core.solutions)",
            code="solutions.checksum",
            path=str(directory),
        )


def materialise(task_or_id: TaskSpec | str, name: str, dest: Path | None = None) -> Path:
    """A self-contained directory holding shipped solution ``name`` of a task.

    Args:
        task_or_id: The task or its id.
        name: ``"reference"`` or ``"baseline/<name>"`` (``TaskSpec.solutions``).
        dest: Directory to write (must not exist, or be empty); None uses the shared cache, keyed by
            the pinned checksum (reuse it read-only).

    Returns:
        The directory.

    Raises:
        RleError: Unknown task or solution (``solutions.unknown``), solutions not installed, or the
            materialised bytes differ from the pinned checksum (``solutions.checksum``).
    """
    task = _task(task_or_id)
    sset = declaration(task)
    sol = sset.get(name)
    if dest is not None:
        dest = Path(dest)
        if dest.exists() and any(dest.iterdir()):
            raise RleError(
                f"{dest} is not empty; materialise writes a fresh directory", code="solutions.dest"
            )
        try:
            build(sset, name, dest)
            _check(task.id, sol, dest)
        except BaseException:
            shutil.rmtree(dest, ignore_errors=True)
            raise
        return dest
    root = _writable_root()
    final = root / f"{task.id}__{name.replace('/', '__')}__{sol.sha256[:16]}"
    if final.is_dir():
        if artifact_sha256(final) == sol.sha256:
            return final
        shutil.rmtree(final)  # altered or partial copy: rebuild
    tmp = Path(tempfile.mkdtemp(dir=root, prefix=".build-"))
    try:
        build(sset, name, tmp / "out")
        _check(task.id, sol, tmp / "out")
        try:
            (tmp / "out").rename(final)
        except OSError:
            if not final.is_dir():  # another process may have finished the same directory first
                raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return final


def edit_xml(
    path: Path,
    edit: Callable[[etree._Element], None],
    indent: bool = False,
    final_newline: bool | None = None,
) -> None:
    """Apply ``edit`` to the root element of an MJCF file and write it back with lxml.

    Args:
        path: The file (rewritten in place, UTF-8, no XML declaration).
        edit: Edits the root element in place.
        indent: Re-indent the whole tree with two spaces (``etree.indent``) before writing.
        final_newline: End the file with a newline; None keeps what the file had.
    """
    data = path.read_bytes()
    tree = etree.fromstring(data).getroottree()
    edit(tree.getroot())
    if indent:
        etree.indent(tree, space="  ")
    out = etree.tostring(tree, encoding="utf-8", xml_declaration=False)
    if final_newline is None:
        final_newline = data.endswith(b"\n")
    if final_newline and not out.endswith(b"\n"):
        out += b"\n"
    path.write_bytes(out)


def print_pins() -> None:
    """Print every shipped solution's materialised checksum (to pin after a regeneration)."""
    from rle_tasks.core.registry import all_tasks

    for task in all_tasks():
        if not task.solutions:
            continue
        sset = declaration(task)
        for name in task.solutions:
            with tempfile.TemporaryDirectory() as tmp:
                build(sset, name, Path(tmp) / "s")
                got = artifact_sha256(Path(tmp) / "s")
            pinned = sset.get(name).sha256
            print(
                f"{task.id:<16} {name:<32} {got} {'ok' if got == pinned else 'CHANGED (pinned ' + pinned + ')'}"
            )


if __name__ == "__main__":
    from rle_tasks.core.solutions import print_pins as _print_pins  # the package's classes, not __main__'s

    _print_pins()
