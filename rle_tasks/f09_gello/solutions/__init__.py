"""Shipped solutions of 09-gello, materialised by ``rle_tasks.core.solutions``.

Committed once: ``reference/<robot>/lead.xml`` (written by ``build.py``), the stock meshes in
``assets/<robot>/meshes``, the trim templates in ``assets/trim_templates``, and the one overlay file
``baseline/hanging_trim/trim.py``. Each solution directory holds ``<robot>/{lead.xml, trim.py,
meshes/*.stl}`` for the three robots.

- ``reference``: balanced leaders (``build.py``) and the regressor trim.
- ``baseline/uncompensated``: the stock leaders and the zero trim.
- ``baseline/gravcomp_cheat``: ``uncompensated`` with ``gravcomp="1"`` on every link (forbidden).
- ``baseline/over_mass``: the reference plus a 2.5 kg steel block on the base.
- ``baseline/hanging_trim``: the reference with a trim whose ``adapt`` never returns.

``SOLUTIONS`` is the one table of pinned checksums (``artifact_sha256`` of each materialised directory)
and golden scores (quick mode, public development key).
"""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from rle_tasks.core.solutions import Solution, SolutionSet, edit_xml
from rle_tasks.f09_gello.leaders import ROBOTS


def _per_robot(dest: str, src: str) -> tuple[tuple[str, str], ...]:
    return tuple((f"{r}/{dest}", src.format(robot=r)) for r in ROBOTS)


def _unchanged(root: etree._Element) -> None:
    del root


def reindent_leaders(directory: Path) -> None:
    """Re-serialise each ``lead.xml`` with lxml (two-space indent, no final newline), as ``build.py`` does."""
    for robot in ROBOTS:
        edit_xml(directory / robot / "lead.xml", _unchanged, indent=True, final_newline=False)


def _gravcomp_links(root: etree._Element) -> None:
    for body in root.iter("body"):
        if body.get("name", "").startswith("link"):
            attrs = list(body.attrib.items())
            body.attrib.clear()
            body.set("gravcomp", "1")
            for key, value in attrs:
                body.set(key, value)


def gravcomp_links(directory: Path) -> None:
    """Set ``gravcomp="1"`` (as the first attribute) on every ``link*`` body of each leader."""
    for robot in ROBOTS:
        edit_xml(directory / robot / "lead.xml", _gravcomp_links)


def _ballast(root: etree._Element) -> None:
    base = next(b for b in root.iter("body") if b.get("name") == "base")
    body = etree.SubElement(base, "body", name="ballast", pos="0.09 0 0.01")  # overlaps the plate edge
    etree.SubElement(
        body,
        "geom",
        name="ballast_steel",
        type="box",
        size="0.045 0.045 0.02",
        mass="2.5434",  # 7850 kg/m^3 x 90 x 90 x 40 mm: a part of catalog steel (issue 45)
        rgba="0.4 0.4 0.4 1",
    )


def steel_ballast(directory: Path) -> None:
    """Add a 2.54 kg steel block (90 x 90 x 40 mm), overlapping the base plate's edge, to each leader's
    base: every device then exceeds the 3.00 kg bound (the lightest reference is 1.07 kg)."""
    for robot in ROBOTS:
        edit_xml(directory / robot / "lead.xml", _ballast, indent=True)


SOLUTIONS = SolutionSet(
    package="rle_tasks.f09_gello",
    solutions=(
        Solution(
            "reference",
            sha256="a40d29a9946258ae3e1ad7691dfb0defa8f3c944a5c20afacc6b746888feb1d6",
            quick_score=0.859969557003,
            files=_per_robot("lead.xml", "solutions/reference/{robot}/lead.xml")
            + _per_robot("meshes", "assets/{robot}/meshes")
            + _per_robot("trim.py", "assets/trim_templates/regressor_trim.py"),
        ),
        Solution(
            "baseline/uncompensated",
            sha256="3f3cd52f4dedd4f12edcba96dd8e9b619b45e65b8b0671774a407a4ffae8bebc",
            quick_score=0.113598124186,
            base="reference",
            files=_per_robot("lead.xml", "assets/{robot}/lead.xml")
            + _per_robot("trim.py", "assets/trim_templates/zero_trim.py"),
            transforms=(reindent_leaders,),
        ),
        Solution(
            "baseline/gravcomp_cheat",
            sha256="08874c2d1b5a20c0dd852476c773969c5ed10b274cdc0d3539f5abb95d551051",
            quick_score=0.0,
            base="baseline/uncompensated",
            transforms=(gravcomp_links,),
        ),
        Solution(
            "baseline/over_mass",
            sha256="a935e49576471317a03ee66fcc14a5fe7ef69c77a8a4debf383de5b135dd3474",
            quick_score=0.0,
            base="reference",
            transforms=(steel_ballast,),
        ),
        Solution(
            "baseline/hanging_trim",
            sha256="4cf8b437fbc9e62e36704fb1c3bb5f7d05a67df4471f5b4bdb1154310973af91",
            quick_score=0.424395481164,
            base="reference",
            files=_per_robot("trim.py", "solutions/baseline/hanging_trim/trim.py"),
        ),
    ),
)
