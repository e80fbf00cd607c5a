"""Versioned YAML catalogs with SI units, loaded and validated by one function: ``load_catalog``.

Every catalog file declares ``units`` for each numeric field; an entry that carries a number without a
declared unit, a duplicate or unsorted id, or a missing required field is rejected.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from rle_design.errors import CatalogError
from rle_design.paths import CATALOG_DIR


@dataclass(frozen=True)
class Profile:
    """T-slot aluminium extrusion."""

    id: str
    width: float  # [m]
    height: float  # [m]
    area: float  # [m^2]
    linear_mass: float  # [kg/m]
    ix: float  # [m^4]
    iy: float  # [m^4]
    cost: float  # [EUR/m]
    max_length: float  # [m]


@dataclass(frozen=True)
class Material:
    """A solid material: nominal density, the range a real part of it spans, stiffness and strength."""

    id: str
    density: float  # [kg/m^3]
    youngs_modulus: float  # [Pa]
    yield_strength: float  # [Pa]
    density_min: float | None = None  # [kg/m^3] lightest real part of this material (default: density)
    density_max: float | None = None  # [kg/m^3] heaviest real part of this material (default: density)
    tensile_strength: float | None = None  # [Pa] ultimate tensile strength (default: yield_strength)

    @property
    def density_range(self) -> tuple[float, float]:
        """(lightest, heaviest) density a part of this material may declare [kg/m^3]."""
        lo = self.density if self.density_min is None else self.density_min
        hi = self.density if self.density_max is None else self.density_max
        return float(lo), float(hi)


@dataclass(frozen=True)
class Servo:
    id: str
    mass: float  # [kg]
    gear_ratio: float  # [1]
    stall_torque: float  # [N m]
    torque_limit: float  # [N m]
    stall_current: float  # [A]
    torque_constant: float  # [N m/A]
    coulomb_friction: float  # [N m]
    viscous_friction: float  # [N m s/rad]
    reflected_inertia: float  # [kg m^2]
    size: tuple[float, float, float]  # [m]
    voltage: float  # [V]


@dataclass(frozen=True)
class Arm:
    id: str
    model: str  # "package:relative/path" of the MJCF
    dof: int
    mass: float  # [kg]
    reach: float  # [m]
    rated_payload: float  # [kg]
    base_footprint: tuple[float, float]  # [m]
    shoulder_height: float  # [m]
    root_body: str
    tool_body: str
    mount_frame: str


@dataclass(frozen=True)
class Part:
    id: str
    fragment: str  # path relative to rle_design/catalogs/
    mass: float  # [kg]
    params: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Spring:
    """Music-wire compression spring worked in tension through a cable (``springs.yaml``)."""

    id: str
    wire_diameter: float  # [m]
    mean_diameter: float  # [m]
    active_coils: int  # [1]
    free_length: float  # [m]
    solid_length: float  # [m]
    rate: float  # [N/m]
    max_force: float  # [N]
    max_stroke: float  # [m]
    mass: float  # [kg]


@dataclass(frozen=True)
class TorsionSpring:
    """Music-wire helical torsion spring about a joint axis (``torsion_springs.yaml``)."""

    id: str
    wire_diameter: float  # [m]
    mean_diameter: float  # [m]
    body_coils: int  # [1]
    rate: float  # [N m/rad]
    max_moment: float  # [N m]
    max_angle: float  # [rad]
    mass: float  # [kg]


@dataclass(frozen=True)
class ShelfTarget:
    id: str
    pos: tuple[float, float, float]  # [m]


_ENTRY_TYPES: dict[str, type] = {
    "profiles": Profile,
    "materials": Material,
    "servos": Servo,
    "arms": Arm,
    "parts": Part,
    "shelf": ShelfTarget,
    "springs": Spring,
    "torsion_springs": TorsionSpring,
}


@dataclass(frozen=True)
class Catalog:
    """A loaded catalog: entries in id order plus the file's top-level data.

    Attributes:
        kind: Catalog kind, e.g. ``"profiles"``.
        version: Integer version of the file format and data.
        units: Unit of every numeric field, e.g. ``{"linear_mass": "kg/m"}``.
        source: Where the numbers come from.
        entries: Entries, sorted by id.
        extra: Other top-level fields (e.g. ``print_rules`` for materials, shelf geometry).
    """

    kind: str
    version: int
    units: Mapping[str, str]
    source: str
    entries: tuple[Any, ...]
    extra: Mapping[str, Any]

    @property
    def ids(self) -> list[str]:
        return [e.id for e in self.entries]

    def get(self, entry_id: str) -> Any:
        """Entry by id; raises ``CatalogError`` listing the valid ids."""
        for e in self.entries:
            if e.id == entry_id:
                return e
        raise CatalogError(
            f"{self.kind} entry '{entry_id}' does not exist. Available: {', '.join(self.ids)}",
            code="catalog.unknown_entry",
        )

    def __iter__(self):
        return iter(self.entries)

    def __len__(self) -> int:
        return len(self.entries)


def catalog_kinds() -> list[str]:
    return sorted(_ENTRY_TYPES)


def _check_units(kind: str, where: str, data: Mapping[str, Any], units: Mapping[str, str]) -> None:
    for key, value in data.items():
        numeric = isinstance(value, int | float) and not isinstance(value, bool)
        if isinstance(value, list) and value and all(isinstance(v, int | float) for v in value):
            numeric = True
        if numeric and key not in units:
            raise CatalogError(
                f"catalog '{kind}': {where} field '{key}' is a number without a declared unit "
                f"(declared: {', '.join(sorted(units))})",
                code="catalog.missing_unit",
            )


def _build_entry(kind: str, raw: Mapping[str, Any], units: Mapping[str, str]) -> Any:
    cls = _ENTRY_TYPES[kind]
    names = [f.name for f in dataclasses.fields(cls)]
    if "id" not in raw:
        raise CatalogError(f"catalog '{kind}': an entry has no 'id'", code="catalog.invalid")
    eid = str(raw["id"])
    _check_units(kind, f"entry '{eid}'", {k: v for k, v in raw.items() if k != "id"}, units)
    values: dict[str, Any] = {"id": eid}
    if cls is Part:
        values["fragment"] = raw.get("fragment")
        values["mass"] = raw.get("mass")
        values["params"] = {k: v for k, v in raw.items() if k not in ("id", "fragment", "mass")}
    else:
        optional = {f.name for f in dataclasses.fields(cls) if f.default is not dataclasses.MISSING}
        for name in names[1:]:
            if name not in raw and name in optional:
                continue
            if name not in raw:
                raise CatalogError(
                    f"catalog '{kind}': entry '{eid}' lacks required field '{name}'",
                    code="catalog.invalid",
                )
            v = raw[name]
            values[name] = tuple(float(x) for x in v) if isinstance(v, list) else v
        unknown = sorted(set(raw) - set(names))
        if unknown:
            raise CatalogError(
                f"catalog '{kind}': entry '{eid}' has unknown fields {unknown}; allowed: {names}",
                code="catalog.invalid",
            )
    for name, v in values.items():
        if name in units and (isinstance(v, (str, bool))):
            raise CatalogError(
                f"catalog '{kind}': entry '{eid}' field '{name}' is not a number: {v!r} (YAML reads "
                "1.5e9 as text; write 1.5e+9)",
                code="catalog.invalid",
            )
        if v is None:
            raise CatalogError(f"catalog '{kind}': entry '{eid}' lacks '{name}'", code="catalog.invalid")
        if isinstance(v, float | int) and not isinstance(v, bool) and name != "id" and v <= 0:
            raise CatalogError(
                f"catalog '{kind}': entry '{eid}' field '{name}' must be positive, got {v}",
                code="catalog.invalid",
            )
    return cls(**values)


@functools.cache
def load_catalog(kind: str, directory: str | None = None) -> Catalog:
    """Load and validate ``rle_design/catalogs/<kind>.yaml`` (package data).

    Args:
        kind: One of ``catalog_kinds()``.
        directory: Alternative catalog directory (tests); defaults to ``CATALOG_DIR``.

    Raises:
        CatalogError: Unknown kind, unreadable file, missing units, duplicate or unsorted ids.
    """
    if kind not in _ENTRY_TYPES:
        raise CatalogError(
            f"catalog kind '{kind}' does not exist. Available kinds: {', '.join(catalog_kinds())}",
            code="catalog.unknown_kind",
        )
    path = Path(directory) if directory else CATALOG_DIR
    path = path / f"{kind}.yaml"
    try:
        data = yaml.safe_load(path.read_text())
    except FileNotFoundError:
        raise CatalogError(f"catalog file {path} not found", code="catalog.missing_file") from None
    except yaml.YAMLError as exc:
        raise CatalogError(f"catalog file {path} is not valid YAML: {exc}", code="catalog.invalid") from None
    if not isinstance(data, dict) or data.get("kind") != kind:
        raise CatalogError(f"catalog file {path} must be a mapping with kind: {kind}", code="catalog.invalid")
    for key in ("version", "units", "source", "entries"):
        if key not in data:
            raise CatalogError(f"catalog file {path} lacks '{key}'", code="catalog.invalid")
    units = dict(data["units"])
    entries = tuple(_build_entry(kind, raw, units) for raw in data["entries"])
    ids = [e.id for e in entries]
    if len(set(ids)) != len(ids):
        raise CatalogError(f"catalog '{kind}' has duplicate ids: {ids}", code="catalog.invalid")
    if ids != sorted(ids) and kind != "shelf":
        raise CatalogError(f"catalog '{kind}' ids must be sorted: {ids}", code="catalog.invalid")
    extra = {k: v for k, v in data.items() if k not in ("version", "kind", "units", "source", "entries")}
    _check_units(kind, "top-level", {k: v for k, v in extra.items() if not isinstance(v, dict)}, units)
    return Catalog(kind, int(data["version"]), units, str(data["source"]).strip(), entries, extra)


def part_fragment_path(part: Part) -> Path:
    """Absolute path of a part's MJCF fragment."""
    return CATALOG_DIR / part.fragment
