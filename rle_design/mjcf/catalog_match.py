"""Match aluminium-profile geoms of a design against ``catalogs/profiles.yaml``.

Convention: an extrusion is a box geom named ``profile_<catalog id>_<anything>`` (e.g.
``profile_4040_left_rail``; ``profile_<id>`` alone is accepted too). Its three full sizes are taken
from the compiled model (so ``fromto``, ``size`` and default classes all work); the two smaller full
sizes must equal the catalog ``width`` and ``height`` within ``SECTION_TOL`` (either order), the
largest is the profile's length, which must not exceed the catalog ``max_length``. The geom must
carry an explicit ``mass`` attribute equal to length x ``linear_mass`` within ``MASS_RTOL``.

Findings (codes): ``catalog.unknown_profile`` (lists the catalog ids), ``catalog.not_a_box``,
``catalog.section_mismatch``, ``catalog.too_long``, ``catalog.missing_mass``,
``catalog.mass_mismatch`` (message with both numbers). Totals use the catalog (expected) mass and
cost of every recognised profile.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from lxml import etree

from rle_design.catalog import load_catalog
from rle_design.mjcf.contract import Finding
from rle_design.mjcf.loader import Design
from rle_design.scene.elements import element_id, has_element

__all__ = ["MASS_RTOL", "PREFIX", "SECTION_TOL", "ProfileReport", "ProfileUse", "match_profiles"]

PREFIX = "profile_"
SECTION_TOL = 0.0005  # [m]
MASS_RTOL = 0.02


@dataclass(frozen=True)
class ProfileUse:
    """One profile geom.

    Attributes:
        geom: Geom name.
        profile_id: Catalog id (e.g. ``"4040"``).
        length: Largest full size [m].
        expected_mass: length x linear_mass [kg].
        declared_mass: The geom's ``mass`` attribute [kg] (None when absent).
        cost: length x cost per metre [EUR].
    """

    geom: str
    profile_id: str
    length: float
    expected_mass: float
    declared_mass: float | None
    cost: float


@dataclass(frozen=True)
class ProfileReport:
    """Profiles found in a design.

    Attributes:
        profiles: Recognised profile geoms, in document order.
        findings: Violations of the convention.
        total_length: Sum of profile lengths [m].
        total_mass: Sum of expected (catalog) masses [kg].
        total_cost: Sum of costs [EUR].
    """

    profiles: tuple[ProfileUse, ...]
    findings: tuple[Finding, ...]
    total_length: float
    total_mass: float
    total_cost: float

    @property
    def ok(self) -> bool:
        return not self.findings


def match_profiles(
    design_or_tree: Design | etree._Element | etree._ElementTree, model: mujoco.MjModel
) -> ProfileReport:
    """Check every ``profile_*`` geom of a design against the profile catalog.

    Args:
        design_or_tree: A ``Design`` (findings then carry file and line) or an lxml tree/element.
        model: The compiled model of that design (full sizes are read from ``geom_size``).
    """
    catalog = load_catalog("profiles")
    if isinstance(design_or_tree, Design):
        root = design_or_tree.tree.getroot()
        where = design_or_tree.where
    else:
        root = design_or_tree.getroot() if isinstance(design_or_tree, etree._ElementTree) else design_or_tree
        where = lambda el: (None, el.sourceline)  # noqa: E731
    uses: list[ProfileUse] = []
    findings: list[Finding] = []
    for el in root.iter("geom"):
        name = el.get("name") or ""
        if not name.startswith(PREFIX):
            continue
        path, line = where(el)

        def add(code: str, message: str, el=el, path=path, line=line) -> None:
            findings.append(Finding(code, message, element="geom", line=line, path=path))

        pid = name[len(PREFIX) :].split("_", 1)[0]
        if pid not in catalog.ids:
            add(
                "catalog.unknown_profile",
                f"geom '{name}': profile '{pid}' is not in the catalog. Available profiles: "
                f"{', '.join(catalog.ids)}",
            )
            continue
        prof = catalog.get(pid)
        gid = element_id(model, "geom", name) if has_element(model, "geom", name) else None
        if gid is None or model.geom_type[gid] != mujoco.mjtGeom.mjGEOM_BOX:
            add("catalog.not_a_box", f"geom '{name}': a profile must be a box geom")
            continue
        sizes = np.sort(2.0 * model.geom_size[gid])
        section, length = sizes[:2], float(sizes[2])
        want = np.sort([prof.width, prof.height])
        if np.any(np.abs(section - want) > SECTION_TOL):
            add(
                "catalog.section_mismatch",
                f"geom '{name}': section {section[0] * 1e3:.1f} x {section[1] * 1e3:.1f} mm != profile "
                f"{pid} {want[0] * 1e3:.1f} x {want[1] * 1e3:.1f} mm (tolerance {SECTION_TOL * 1e3:.1f} mm)",
            )
        if length > prof.max_length:
            add(
                "catalog.too_long",
                f"geom '{name}': length {length:.3f} m > {pid} max length {prof.max_length} m",
            )
        expected = length * prof.linear_mass
        raw_mass = el.get("mass")
        declared = None
        if raw_mass is None:
            add("catalog.missing_mass", f"geom '{name}': a profile must declare mass=\"{expected:.3f}\" (kg)")
        else:
            try:
                declared = float(raw_mass)
            except ValueError:
                add("catalog.missing_mass", f"geom '{name}': mass '{raw_mass}' is not a number")
            else:
                if abs(declared - expected) > MASS_RTOL * expected:
                    add(
                        "catalog.mass_mismatch",
                        f"geom '{name}': mass {declared:.3f} kg != length {length:.3f} m x "
                        f"{prof.linear_mass:.3f} kg/m = {expected:.3f} kg",
                    )
        uses.append(ProfileUse(name, pid, length, expected, declared, length * prof.cost))
    return ProfileReport(
        profiles=tuple(uses),
        findings=tuple(findings),
        total_length=float(sum(u.length for u in uses)),
        total_mass=float(sum(u.expected_mass for u in uses)),
        total_cost=float(sum(u.cost for u in uses)),
    )
