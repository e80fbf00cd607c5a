"""The object catalogue's data (``catalogue.yaml``): categories, their instances with source, licence
and origin, and the installed distribution that holds each instance's files (located through the
import system's metadata, never imported)."""

from __future__ import annotations

import functools
import importlib.metadata
from dataclasses import dataclass
from pathlib import Path

import yaml

from rle_design.paths import package_dir

DATA = Path(__file__).with_name("catalogue.yaml")
"""The catalogue's data file."""


@dataclass(frozen=True)
class Instance:
    """One object of a category.

    Attributes:
        id: ``<source>/<name>``.
        category: Its category.
        source: Source key of ``catalogue.yaml`` (robosuite, gso, hope, turbosquid, libero).
        package: Installed package that holds it.
        path: Its MJCF, relative to the package directory.
        licence: SPDX identifier, or ``unknown``.
        origin: Where the model comes from.
    """

    id: str
    category: str
    source: str
    package: str
    path: str
    licence: str
    origin: str

    @property
    def xml(self) -> Path:
        """Absolute path of the instance's MJCF."""
        return package_dir(self.package) / self.path

    @property
    def wheel(self) -> str:
        """The installed distribution (``name==version``) whose RECORD lists the MJCF."""
        return _wheel_of(self.package, self.path)


@dataclass(frozen=True)
class Category:
    """A category: its name, the rgba of its visual geoms, its instance ids, its grasp mode
    (``catalogue_grasp.MODES``), the typical mass [kg] of the real product its first instance models and
    where that number comes from, where the reference grasp planner can take none of its instances, why
    (``not_graspable``), and a rest rotation (w, x, y, z) of the body frame where the category stands
    otherwise than the source lays it (``rest``)."""

    name: str
    rgba: tuple[float, float, float, float]
    instances: tuple[str, ...]
    grasp: str
    mass: float
    mass_source: str
    not_graspable: str | None = None
    rest: tuple[float, float, float, float] | None = None


@functools.cache
def _data() -> dict:
    return yaml.safe_load(DATA.read_text())


def _categories() -> dict[str, Category]:
    return {
        name: Category(
            name,
            tuple(c["rgba"]),
            tuple(c["instances"]),
            c.get("grasp", "top"),
            float(c["mass"]),
            " ".join(c["mass_source"].split()),
            c.get("not_graspable"),
            tuple(float(v) for v in c["rest"]) if "rest" in c else None,
        )
        for name, c in _data()["categories"].items()
    }


CATEGORIES: dict[str, Category] = _categories()
"""Every category by name."""


@functools.cache
def instance(instance_id: str) -> Instance:
    """The instance ``<source>/<name>``."""
    category = next((c.name for c in CATEGORIES.values() if instance_id in c.instances), None)
    if category is None:
        raise KeyError(f"no catalogue instance '{instance_id}'")
    key, name = instance_id.split("/", 1)
    src = _data()["sources"][key]
    rel = f"{name}.xml" if key == "robosuite" else f"{name}/{name}.xml"
    return Instance(
        id=instance_id,
        category=category,
        source=key,
        package=src["package"],
        path=f"{src['root']}/{rel}",
        licence=src["licence"],
        origin=" ".join(src["origin"].split()),
    )


def instances(category: str | None = None) -> tuple[str, ...]:
    """Instance ids of one category, or of all in catalogue order."""
    cats = [CATEGORIES[category]] if category else CATEGORIES.values()
    return tuple(i for c in cats for i in c.instances)


@functools.cache
def _records() -> dict[str, str]:
    """Installed file (``package/path``) -> ``name==version`` of the catalogue's source distributions."""
    roots = {f"{s['package']}/{s['root']}" for s in _data()["sources"].values()}
    index = {}
    for dist in importlib.metadata.distributions():
        for f in dist.files or ():
            name = str(f)
            if any(name.startswith(r) for r in roots):
                index[name] = f"{dist.metadata['Name']}=={dist.version}"
    return index


def _wheel_of(package: str, path: str) -> str:
    wheel = _records().get(f"{package}/{path}")
    if wheel is None:
        raise FileNotFoundError(f"no installed distribution lists {package}/{path}")
    return wheel
