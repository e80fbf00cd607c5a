"""Shipped solutions of 08-mobile-base, materialised by ``rle_tasks.core.solutions``.

Committed once: ``reference/{robot.xml, controller.py}`` (the frame written by ``design_gen.py``) and,
per baseline, only the file that differs. Each solution directory holds ``robot.xml`` and
``controller.py``.

- ``reference``: 4040 frame, adapter on a four-post tower, the planning controller.
- ``baseline/bad_mount``: long, low frame with the mount at the rear (``design_gen.BAD_MOUNT``).
- ``baseline/non_catalog_profile``: the reference with one rail renamed to a profile not in the catalog.
- ``baseline/raising_controller``: the reference frame with a controller that raises.
- ``baseline/tall_narrow``: small footprint, 0.75 m tower (``design_gen.TALL_NARROW``).

``SOLUTIONS`` is the one table of pinned checksums (``artifact_sha256`` of each materialised directory)
and golden scores (quick mode, public development key).
"""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from rle_tasks.core.solutions import Solution, SolutionSet, edit_xml

NON_CATALOG_GEOM = "profile_5050_rail_left"
"""The renamed rail of ``baseline/non_catalog_profile`` (5050 is not a catalog profile)."""


def _rename_left_rail(root: etree._Element) -> None:
    geom = next(g for g in root.iter("geom") if g.get("name") == "profile_4040_rail_left")
    geom.set("name", NON_CATALOG_GEOM)


def non_catalog_rail(directory: Path) -> None:
    """Rename the left rail's profile id to ``5050`` (not in ``profiles.yaml``)."""
    edit_xml(directory / "robot.xml", _rename_left_rail)


SOLUTIONS = SolutionSet(
    package="rle_tasks.f08_mobile_base",
    solutions=(
        Solution(
            "reference",
            sha256="c6494d1e72dbe28463e492a77eaea5aee611d97fd5fed62d830dda99c4be7574",
            quick_score=0.815564973125,
            files=((".", "solutions/reference"),),
        ),
        Solution(
            "baseline/bad_mount",
            sha256="fbe8856dca20b9a97d6abf99e3c5ad398dfed573d1e95383250f4598c9f103c1",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/bad_mount/robot.xml"),),
        ),
        Solution(
            "baseline/non_catalog_profile",
            sha256="b9a915a7352a4e43a2ce8896751dd01c677c83c3ffd28706327603c1011a3555",
            quick_score=0.15,
            base="reference",
            transforms=(non_catalog_rail,),
        ),
        Solution(
            "baseline/raising_controller",
            sha256="05f237297bec48aa150387d7f2d5448dabd37164d652d26303375e143c957eed",
            quick_score=0.15,
            base="reference",
            files=(("controller.py", "solutions/baseline/raising_controller/controller.py"),),
        ),
        Solution(
            "baseline/tall_narrow",
            sha256="e0d7248479ab56450ce8a3704a945727186d028ddf07c8de5bf3b3aa3f072ad1",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/tall_narrow/robot.xml"),),
        ),
    ),
)
