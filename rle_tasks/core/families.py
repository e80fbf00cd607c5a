"""The families data file (``families.yaml``): family numbers, folders, workflows, placeholder tasks."""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from importlib import resources

import yaml

from rle_design.errors import RleError

__all__ = ["FamilyInfo", "Placeholder", "families", "family", "placeholders", "workflow_order"]

_FOLDER = re.compile(r"f(\d\d)_([a-z0-9_]+)")


class FamilyDataError(RleError):
    """``families.yaml`` is malformed or disagrees with a family folder."""

    code = "registry.families"


@dataclass(frozen=True)
class FamilyInfo:
    """One line of ``families``.

    Attributes:
        number: Family number (task ids start with it, two digits).
        slug: Folder suffix: the package is ``rle_tasks.f<NN>_<slug>``.
        workflow: One of ``workflow_order()``.
        title: Human title.
    """

    number: int
    slug: str
    workflow: str
    title: str

    @property
    def package(self) -> str:
        return f"rle_tasks.f{self.number:02d}_{self.slug}"


@dataclass(frozen=True)
class Placeholder:
    """A task registered before its family implements it."""

    id: str
    title: str

    @property
    def family(self) -> int:
        return int(self.id[:2])


@functools.cache
def _data() -> dict:
    text = resources.files("rle_tasks.core").joinpath("families.yaml").read_text()
    data = yaml.safe_load(text)
    for key in ("workflows", "families", "placeholders"):
        if key not in (data or {}):
            raise FamilyDataError(f"families.yaml has no '{key}' section")
    return data


@functools.cache
def workflow_order() -> tuple[str, ...]:
    """The four workflows in the paper's order."""
    return tuple(_data()["workflows"])


@functools.cache
def families() -> tuple[FamilyInfo, ...]:
    """Every family line, in family order."""
    out = []
    for row in _data()["families"]:
        info = FamilyInfo(int(row["number"]), str(row["slug"]), str(row["workflow"]), str(row["title"]))
        if info.workflow not in workflow_order():
            raise FamilyDataError(
                f"family {info.number} has workflow '{info.workflow}'. Known workflows: "
                f"{', '.join(workflow_order())}"
            )
        out.append(info)
    numbers = [f.number for f in out]
    if numbers != sorted(set(numbers)):
        raise FamilyDataError(f"family numbers must be unique and sorted, got {numbers}")
    return tuple(out)


def family(number: int) -> FamilyInfo:
    """The line of family ``number``; raises listing the known families."""
    for f in families():
        if f.number == number:
            return f
    known = ", ".join(f"{f.number:02d} ({f.slug})" for f in families())
    raise FamilyDataError(f"family {number:02d} is not in families.yaml. Known families: {known}")


def folder_family(folder: str) -> int | None:
    """Family number of a package folder named ``f<NN>_<slug>``, else None."""
    m = _FOLDER.fullmatch(folder)
    return int(m.group(1)) if m else None


@functools.cache
def placeholders() -> tuple[Placeholder, ...]:
    """Placeholder tasks in paper order."""
    out = tuple(Placeholder(str(r["id"]), str(r["title"])) for r in _data()["placeholders"])
    for p in out:
        family(p.family)
    return out
