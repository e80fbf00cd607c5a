"""Registry of every task: family packages are discovered, the rest come from ``families.yaml``.

A family package is a folder ``rle_tasks/f<NN>_<slug>/`` whose ``__init__`` defines
``tasks() -> list[TaskSpec]`` and whose number and slug have a line in ``families.yaml``. Its tasks
replace the placeholders of the same ids; placeholders it does not implement stay registered with
``implemented = False``. Core never names a family: discovery is by folder.
"""

from __future__ import annotations

import functools
import importlib
import pkgutil
from collections.abc import Iterable

import rle_tasks
from rle_design.errors import RleError
from rle_tasks.core import families as _data
from rle_tasks.core.families import FamilyDataError, family, folder_family, placeholders
from rle_tasks.core.task import TaskSpec


def family_packages(search: Iterable[str] | None = None, prefix: str = "rle_tasks.") -> dict[int, str]:
    """Family number -> importable package name of every ``f<NN>_<slug>`` folder found.

    Args:
        search: Directories to scan; defaults to the ``rle_tasks`` package.
        prefix: Module prefix of the packages found there.

    Raises:
        FamilyDataError: A folder without its line in ``families.yaml``, or with another slug.
    """
    found: dict[int, str] = {}
    for mod in pkgutil.iter_modules(list(search) if search is not None else list(rle_tasks.__path__)):
        number = folder_family(mod.name)
        if number is None or not mod.ispkg:
            continue
        info = family(number)
        if mod.name != f"f{number:02d}_{info.slug}":
            raise FamilyDataError(
                f"family folder '{mod.name}' does not match its line in families.yaml "
                f"(expected 'f{number:02d}_{info.slug}')"
            )
        found[number] = prefix + mod.name
    return dict(sorted(found.items()))


def collect(packages: dict[int, str]) -> tuple[TaskSpec, ...]:
    """Placeholders in paper order, replaced or extended by the tasks of ``packages``."""
    specs = {p.id: TaskSpec(p.id, p.family, p.title) for p in placeholders()}
    for number, name in packages.items():
        for spec in importlib.import_module(name).tasks():
            if spec.family != number or not spec.id.startswith(f"{number:02d}-"):
                raise RleError(f"package {name} registers task '{spec.id}' of family {spec.family:02d}")
            specs[spec.id] = spec
    order = {f.number: i for i, f in enumerate(_data.families())}
    listed = {p.id: i for i, p in enumerate(placeholders())}
    return tuple(sorted(specs.values(), key=lambda s: (order[s.family], listed.get(s.id, len(listed)), s.id)))


@functools.cache
def all_tasks() -> tuple[TaskSpec, ...]:
    """Every registered task, in paper order; implemented families replace their placeholders."""
    return collect(family_packages())


def get_task(task_id: str) -> TaskSpec:
    """Task by id; raises ``RleError`` listing close matches.

    Besides the registered tasks, a family package may resolve ids of its evaluation stages with
    ``stage_task(task_id) -> TaskSpec | None`` (family 02's fresh agents, ``02-group-NN-fresh-K``): tasks
    an operator runs as trials of their own, not among the 51."""
    for spec in all_tasks():
        if spec.id == task_id:
            return spec
    prefix = task_id.split("-")[0]
    if prefix.isdigit() and (name := family_packages().get(int(prefix))) is not None:
        stage = getattr(importlib.import_module(name), "stage_task", None)
        if stage is not None and (spec := stage(task_id)) is not None:
            return spec
    ids = [s.id for s in all_tasks()]
    close = [i for i in ids if i.split("-")[0] == task_id.split("-")[0]] or ids
    raise RleError(f"task '{task_id}' does not exist. Known ids: {', '.join(close)}", code="task.unknown")
