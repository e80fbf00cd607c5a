"""Kitchen layout kinds: today's one-wall kitchens unchanged (pinned digests), runs that neither overlap
nor leave a gap at a corner, the placement rules, fixture frames that match the compiled bodies, style
variation and the pretrain/target split over kind x style family."""

import hashlib
import itertools
import math

import mujoco
import numpy as np
import pytest

from rle_design.control.env import portable_digest
from rle_tasks.envs.kitchen import fixture as fx
from rle_tasks.envs.kitchen.layout import CORNER_LEG, FLAT, KINDS, build_layout
from rle_tasks.envs.kitchen.layout_kinds import sample_layout
from rle_tasks.envs.kitchen.layout_scene import layout_xml
from rle_tasks.envs.kitchen.scene import build_scene
from rle_tasks.envs.kitchen.styles import FAMILIES, combinations, split

SEEDS = range(6)
SCENES = {
    (1_000_003, "OpenFridge", 0): "9ac30b590be1e0985bd7674d9a84b9c762be6a511c10cf4130b78bda6de1402d",
    (1_000_010, "TurnOnStove", 3): "0de84261a42e7e71f04cd71853bc872a7ea6ecabfd475ffd1fcdf5acfe751548",
    (1125461247574613424, "PickPlaceCounterToDrawer", 3667311847939662570): (
        "2cc6529d8a54180156f9d06448ae1fe6d840ee5311e647615be64c7f72e84708"
    ),
}
"""Model digests of family-01 scenes (pretrain kitchens 0 and 7; the public key's first target of
pnp-counter-to-drawer), recorded before layouts had kinds."""
LAYOUTS_DIGEST = "0b49d59c9efe47a0a98eccb13fa7cd8b11da85faa9a401e4ad5151483e755c30"
"""sha256 of the layout-only MJCF of layout seeds 0-20 and the 50 pretrain seeds, in order."""


@pytest.mark.parametrize("key", list(SCENES))
def test_one_wall_scenes_keep_their_model_digests(key):
    assert portable_digest(build_scene(*key).xml) == SCENES[key]


def test_one_wall_layouts_keep_their_mjcf():
    h = hashlib.sha256()
    for seed in [*range(21), *(1_000_003 + k for k in range(50))]:
        spec = mujoco.MjSpec()
        build_layout(spec, sample_layout(np.random.default_rng(seed)))
        h.update(spec.to_xml().encode())
    assert h.hexdigest() == LAYOUTS_DIGEST


def test_default_kind_is_the_one_wall_kitchen_with_the_same_draws():
    a, b = np.random.default_rng(5), np.random.default_rng(5)
    assert sample_layout(a) == sample_layout(b, kind="one_wall")
    assert a.random() == b.random()
    with pytest.raises(ValueError, match="unknown layout kind"):
        sample_layout(a, kind="g_shaped")


def _compiled(layout):
    xml, fixtures = layout_xml(layout)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data, fixtures


def _boxes(model, data):
    """(owner, geom name, lo, hi): world boxes of the collision geoms; the owner is the fixture's root
    body, or the geom itself for geoms on the world or a run body (walls, hood)."""
    out = []
    for g in range(model.ngeom):
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE or model.geom_contype[g] == 0:
            continue
        b = model.geom_bodyid[g]
        while b and model.body_parentid[b] and not model.body(model.body_parentid[b]).name.startswith("run_"):
            b = model.body_parentid[b]
        owner = model.geom(g).name if b == 0 or model.body(b).name.startswith("run_") else model.body(b).name
        rot = data.geom_xmat[g].reshape(3, 3)
        c = data.geom_xpos[g] + rot @ model.geom_aabb[g, :3]
        h = np.abs(rot) @ model.geom_aabb[g, 3:]
        out.append((owner, model.geom(g).name, c - h, c + h))
    return out


@pytest.mark.parametrize("kind", KINDS)
def test_no_two_fixtures_overlap_and_corners_have_no_gap(kind):
    for seed in SEEDS:
        layout = sample_layout(np.random.default_rng(seed), kind=kind)
        model, data, fixtures = _compiled(layout)
        boxes = _boxes(model, data)
        owner = np.array([b[0] for b in boxes])
        lo, hi = np.array([b[2] for b in boxes]), np.array([b[3] for b in boxes])
        ov = np.minimum(hi[:, None], hi[None]) - np.maximum(lo[:, None], lo[None])
        walls = np.array([b[1] in {g.name for g in _walls(model)} for b in boxes])
        clash = np.all(ov > 1e-6, axis=2) & (owner[:, None] != owner[None]) & ~(walls[:, None] & walls[None])
        pairs = [(boxes[i][1], boxes[j][1]) for i, j in zip(*np.nonzero(np.triu(clash)))]
        assert not pairs, (
            f"{kind}/{seed}: overlapping geoms {pairs[:5]}"
        )  # walls meet (and overlap) at corners
        for leg in (g for g in boxes if g[1].endswith("_leg")):
            touching = [
                b[1]
                for b in boxes
                if b[0] != leg[0]
                and b[0] in fixtures
                and fixtures[b[0]].kind not in ("microwave", "dish_rack", "wall_cabinet")
                and _touch(leg, b)
            ]
            assert touching, f"{kind}/{seed}: nothing abuts the corner piece's leg {leg[1]}"


def _walls(model):
    return [model.geom(g) for g in range(model.ngeom) if model.geom(g).name.split("_")[0] == "wall"]


def _touch(a, b) -> bool:
    """Two boxes share a face: they meet along one horizontal axis and overlap along the other."""
    gap = np.maximum(a[2], b[2]) - np.minimum(a[3], b[3])  # > 0: separated
    return (np.sum(np.abs(gap[:2]) < 1e-6) >= 1) and np.sum(gap[:2] < -0.05) >= 1 and gap[2] < 0


@pytest.mark.parametrize("kind", KINDS[1:])
def test_placement_rules(kind):
    for seed in SEEDS:
        layout = sample_layout(np.random.default_rng(seed), kind=kind)
        model, _, fixtures = _compiled(layout)
        hoods = [g for g in range(model.ngeom) if model.geom(g).name == "range_hood"]
        assert len(hoods) == 1, "one range hood, over the stove"
        for run in layout.runs:
            kinds = [u.kind for u in run.units]
            for i, u in enumerate(run.units):
                assert not u.wall_cabinet or (run.wall and u.kind not in ("fridge", "stove", "corner"))
                if u.kind == "fridge":
                    assert i in (0, len(run.units) - 1), "the fridge stands at a run's end"
                    assert "corner" not in kinds[max(i - 1, 0) : i + 2]
                    assert (i == 0 and run.lead == 0) or (i == len(run.units) - 1 and run.tail == 0)
                    assert u.hinge_left == (i == 0), "hinged on its outer side (the door opens off the run)"
                if u.kind == "stove":
                    assert run.wall, "the stove stands on a wall run (under the hood)"
        r, i = layout.microwave_on
        assert layout.runs[r].units[i].kind in FLAT and layout.runs[r].units[i].width >= 0.6
        r, i = layout.dish_rack_on
        assert layout.runs[r].units[i].kind in FLAT and layout.dish_rack_on != layout.microwave_on
        sink = next(
            (r, i) for r, run in enumerate(layout.runs) for i, u in enumerate(run.units) if u.kind == "sink"
        )
        flat_beside = [
            (sink[0], j)
            for j in (sink[1] - 1, sink[1] + 1)
            if 0 <= j < len(layout.runs[sink[0]].units) and layout.runs[sink[0]].units[j].kind in FLAT
        ]
        if set(flat_beside) - {layout.microwave_on}:
            assert layout.dish_rack_on in flat_beside
        assert len(layout.runs) == {"l_shaped": 2, "u_shaped": 3}.get(kind, 2)


@pytest.mark.parametrize("kind", ["galley", "island", "u_shaped"])
def test_aisles_leave_1_2_m_for_the_base(kind):
    for seed in SEEDS:
        layout = sample_layout(np.random.default_rng(seed), kind=kind)
        _, _, fixtures = _compiled(layout)
        base = [f for f in fixtures.values() if f.pos[2] == 0.0 and f.kind != "corner"]
        for a, b in itertools.combinations(base, 2):
            if abs(math.cos(a.yaw - b.yaw) + 1) > 1e-9:
                continue  # not facing each other
            gap = float(np.dot(np.subtract(b.front, a.front), a.facing))
            along = np.subtract(b.front, a.front) - gap * np.array(a.facing)
            if np.linalg.norm(along) < (a.size[0] + b.size[0]) / 2:
                assert gap >= 1.2 - 1e-9, f"{kind}/{seed}: {a.name} and {b.name} {gap:.2f} m apart"


@pytest.mark.parametrize("kind", KINDS)
def test_fixture_frames_match_the_compiled_bodies(kind):
    layout = sample_layout(np.random.default_rng(3), kind=kind)
    model, data, fixtures = _compiled(layout)
    for f in fixtures.values():
        b = model.body(f.name).id
        assert np.allclose(data.xpos[b], f.pos, atol=1e-9), f.name
        facing = data.xmat[b].reshape(3, 3) @ np.array([0.0, -1.0, 0.0])
        assert np.allclose(facing[:2], f.facing, atol=1e-9), f.name
        if f.kind == "drawer_cabinet":
            axis = data.xaxis[model.joint(f.joints[0]).id]
            assert np.allclose(axis[:2], f.facing, atol=1e-9), "the drawer slides out through the front"
    yaws = {round(f.yaw, 6) for f in fixtures.values()}
    assert len(yaws) == len({round(r.yaw, 6) for r in layout.runs})


@pytest.mark.parametrize("handle", fx.HANDLE_TYPES)
def test_handle_types_and_dimensions_build(handle):
    from dataclasses import replace

    layout = sample_layout(np.random.default_rng(2), kind="l_shaped", family="rustic")
    style = replace(layout.style, handle_type=handle, counter_height=0.89)
    model, data, fixtures = _compiled(replace(layout, style=style))
    for f in fixtures.values():
        if f.kind in ("hinge_cabinet", "drawer_cabinet", "wall_cabinet"):
            assert model.geom(f.sites["handle"]).type == (
                mujoco.mjtGeom.mjGEOM_SPHERE if handle == "knob" else
                mujoco.mjtGeom.mjGEOM_CYLINDER if handle == "bar" else mujoco.mjtGeom.mjGEOM_BOX
            )  # fmt: skip
        if f.kind in ("counter", "drawer_cabinet", "hinge_cabinet", "sink", "stove", "corner"):
            assert f.top == 0.89 and f.size[1] == style.counter_depth
    corner = next(f for f in fixtures.values() if f.kind == "corner")
    assert corner.size[0] == pytest.approx(style.counter_depth + CORNER_LEG)


def _part(part):
    from rle_tasks.envs.kitchen.layout_kinds import sample_part

    return lambda seed: sample_part(np.random.default_rng(seed), part)


def test_split_is_disjoint_and_sees_every_kind_and_family_in_pretrain():
    pre, tgt = set(combinations("pretrain")), set(combinations("target"))
    assert not pre & tgt and len(pre | tgt) == len(KINDS) * len(FAMILIES)
    assert (len(pre), len(tgt)) == (24, 12)
    for k in KINDS:
        assert {f for kk, f in pre if kk == k} and {f for kk, f in tgt if kk == k}
    for f in FAMILIES:
        assert {k for k, ff in pre if ff == f} and {k for k, ff in tgt if ff == f}
    assert split("one_wall", "scandinavian") == "target"
    drawn = {
        part: {(x.kind, x.family) for x in map(_part(part), range(40))} for part in ("pretrain", "target")
    }
    assert drawn["pretrain"] <= pre and drawn["target"] <= tgt and len(drawn["target"]) > 6
    for kind, family in tgt:
        layout = sample_layout(np.random.default_rng(0), kind=kind, family=family)
        assert (layout.kind, layout.family) == (kind, family)


@pytest.mark.parametrize("kind", KINDS[1:])
def test_every_door_and_drawer_opens_fully_beside_corners_and_neighbours(kind):
    """Each door opens to its range (6 N m), each drawer slides out (40 N), the others closed: nothing
    in the way, whichever run it stands on and however the run is turned."""
    for seed in range(2):
        model, data, fixtures = _compiled(sample_layout(np.random.default_rng(seed), kind=kind))
        for f in fixtures.values():
            if f.kind not in ("fridge", "hinge_cabinet", "drawer_cabinet", "wall_cabinet", "microwave"):
                continue
            mujoco.mj_resetData(model, data)
            j = model.joint(f.joints[0]).id
            for _ in range(int(1.5 / model.opt.timestep)):
                data.qfrc_applied[model.jnt_dofadr[j]] = 40.0 if f.kind == "drawer_cabinet" else 6.0
                mujoco.mj_step(model, data)
            q, high = data.qpos[model.jnt_qposadr[j]], model.jnt_range[j][1]
            assert q == pytest.approx(high, abs=0.02), f"{kind}/{seed}: {f.name} opened to {q:.3f} of {high}"


def test_the_segmenter_has_a_word_for_every_fixture_kind():
    """Every fixture of every layout kind gets a label: the L2 segmenter names a geom by its fixture's
    kind, and a kind without a word (the corner unit) raised KeyError in every kitchen with a corner."""
    from rle_tasks.envs.kitchen.segmentation import KIND_WORDS

    kinds = set()
    for kind in KINDS:
        for seed in SEEDS:
            _, fixtures = layout_xml(sample_layout(np.random.default_rng(seed), kind=kind))
            kinds |= {f.kind for f in fixtures.values()}
    assert "corner" in kinds
    assert kinds <= set(KIND_WORDS), sorted(kinds - set(KIND_WORDS))
