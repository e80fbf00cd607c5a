"""Picture sheet of the layout kinds: one PNG per kind, a top-down (orthographic) and a perspective view
of the kitchen of layout seed 0 (the walls but the back one cut away) with the mobile Panda at the
stand pose (``floorplan.stand_pose``) of its sink or stove.

``python -m rle_tasks.envs.kitchen.layout_sheet [OUT_DIR]`` (default
``rle_tasks/f01_robocasa_speedrun/assets/layouts``) writes ``<kind>.png`` (960 x 400, a 128-colour
palette: about 100 kB each).
"""

from __future__ import annotations

import sys
from pathlib import Path

import mujoco
import numpy as np

from rle_design.viz.render import render_image
from rle_tasks.envs.kitchen import floorplan as fp
from rle_tasks.envs.kitchen.layout import KINDS, Layout
from rle_tasks.envs.kitchen.layout_kinds import sample_layout
from rle_tasks.envs.kitchen.layout_scene import layout_xml
from rle_tasks.envs.kitchen.styles import FAMILIES

__all__ = ["render_kind"]

OUT = Path(__file__).resolve().parents[2] / "f01_robocasa_speedrun" / "assets" / "layouts"
VIEW = (480, 400)
"""Width and height of one view [px]."""


def _label(layout: Layout) -> str:
    s = layout.style
    return (
        f"{layout.kind} / {layout.family or 'today'}: {len(layout.units)} base units in {len(layout.runs)} run(s), "
        f"counter {s.counter_height:.2f} m high, {s.counter_depth:.2f} m deep, {s.handle_type} handles"
    )


def render_kind(kind: str, seed: int = 0) -> tuple[np.ndarray, str]:
    """The sheet image (H x W x 3) of ``kind``'s kitchen of layout ``seed``, and its caption: the
    one-wall kitchen as the tasks draw it today, the other kinds in a pretrain style family of theirs."""
    k = KINDS.index(kind)
    family = None if k == 0 else list(FAMILIES)[(k + 1) % len(FAMILIES)]
    layout = sample_layout(np.random.default_rng(seed), kind=kind, family=family)
    _, fixtures = layout_xml(layout)
    first = sorted((f for f in fixtures.values() if f.kind in ("sink", "stove")), key=lambda f: f.name)[0]
    xml, _ = layout_xml(layout, fp.stand_pose(first), size=VIEW)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("initial").id)
    mujoco.mj_forward(model, data)
    units = np.array([f.pos[:2] for f in fixtures.values()])
    lo, hi = units.min(axis=0) - 0.8, units.max(axis=0) + 0.8
    centre = np.array([*(lo + hi) / 2, 0.5])
    span = float(max(hi[0] - lo[0], (hi[1] - lo[1]) * VIEW[0] / VIEW[1]))
    w, h = VIEW
    model.vis.headlight.diffuse[:] = 0.35
    model.vis.headlight.ambient[:] = 0.3
    model.vis.headlight.specular[:] = 0.0
    model.vis.global_.fovy = 30.0
    lit = model.light_diffuse.copy()
    model.light_diffuse[:] = 0.25  # the ceiling light straight below the camera washes the top view out
    top = render_image(model, data, width=w, height=h, lookat=centre, distance=1.9 * span, azimuth=90.0,
                       elevation=-89.9, sites=False, shadows=False)  # fmt: skip
    model.light_diffuse[:] = lit
    for g in range(model.ngeom):  # cut away the walls but the back one in the perspective
        if model.geom(g).name.startswith("wall_") and not model.geom(g).name.startswith("wall_cabinet"):
            model.geom_rgba[g, 3] = 0.0
    persp = render_image(model, data, width=w, height=h, lookat=centre, distance=1.6 * span,
                         azimuth=20.0 if kind == "galley" else 60.0, elevation=-35.0 if kind == "galley" else -40.0, sites=False)  # fmt: skip
    return np.concatenate([top, persp], axis=1), _label(layout)


def save(image: np.ndarray, caption: str, path: Path) -> Path:
    """Write the sheet with its caption as a 128-colour PNG."""
    from PIL import Image, ImageDraw

    img = Image.fromarray(image)
    draw = ImageDraw.Draw(img)
    draw.rectangle([0, 0, img.width, 16], fill=(255, 255, 255))
    draw.text((6, 3), caption, fill=(0, 0, 0))
    path.parent.mkdir(parents=True, exist_ok=True)
    img.quantize(128, dither=Image.Dither.NONE).save(path, optimize=True)
    return path


def main(argv: list[str]) -> None:
    out = Path(argv[0]) if argv else OUT
    for kind in KINDS:
        image, caption = render_kind(kind)
        p = save(image, caption, out / f"{kind}.png")
        print(f"{p}: {p.stat().st_size / 1000:.0f} kB  {caption}")


if __name__ == "__main__":
    main(sys.argv[1:])
