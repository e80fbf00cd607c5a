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
            sha256="88d2adc8fabd573f68289e0613836063a7be43edc71878769820ee07e0340c82",
            quick_score=0.821618033333,
            files=((".", "solutions/reference"),),
        ),
        Solution(
            "baseline/bad_mount",
            sha256="662b1094875343c7692be178636cd44d34c31ccea5052794b08a1123622c6dea",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/bad_mount/robot.xml"),),
        ),
        Solution(
            "baseline/non_catalog_profile",
            sha256="dd05ab0b7064d675b0bdd0ca1018ae4376abfb701fc61b766147a9c11dbd7d8b",
            quick_score=0.15,
            base="reference",
            transforms=(non_catalog_rail,),
        ),
        Solution(
            "baseline/raising_controller",
            sha256="d49fc137dcc3df7dbbed5f130864bd0f7d5ddac6439f0143c4f00549b1383f6d",
            quick_score=0.15,
            base="reference",
            files=(("controller.py", "solutions/baseline/raising_controller/controller.py"),),
        ),
        Solution(
            "baseline/tall_narrow",
            sha256="33ecf7ef22d6870689c8e3e505d405a3925bac6dc5310d905af5544f6f2a74fc",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/tall_narrow/robot.xml"),),
        ),
    ),
)
