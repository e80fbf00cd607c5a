"""The tabletop scene: table edge, arms with grippers, cameras, free bodies, the two-arm option."""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.control import TabletopEnv, zero_action
from rle_design.scene import TabletopConfig, add_free_box, build_tabletop
from rle_design.scene.tabletop import ArmNames, finish, free_body_names


def test_table_edge_and_top_are_where_the_config_says() -> None:
    config = TabletopConfig()
    model = build_tabletop(config).compile()
    table = model.geom("table")
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    top = data.geom_xpos[table.id][2] + table.size[2]
    edge = data.geom_xpos[table.id][0] + table.size[0]
    assert abs(top - config.top_z) < 1e-12 and abs(edge - config.edge_x) < 1e-12
    assert set(config.cameras) <= {model.camera(i).name for i in range(model.ncam)}


def test_single_arm_scene_holds_still_for_one_second_without_warnings() -> None:
    config = TabletopConfig()
    spec = build_tabletop(config)
    add_free_box(spec, "b0", (0.03, 0.02, 0.015), (0.2, 0.1, config.top_z + 0.015))
    finish(spec, config)
    env = TabletopEnv(xml=spec.to_xml(), n_substeps=10, image_size=None)
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    site = model.site(ArmNames("panda/").tool_site).id
    start = data.site_xpos[site].copy()
    for _ in range(50):
        env.step(model, data, zero_action())
    assert free_body_names(model) == ("b0",)
    assert np.linalg.norm(data.site_xpos[site] - start) < 1e-3
    assert not any(w.number for w in data.warning)


def test_two_arms_face_each_other() -> None:
    config = TabletopConfig.two_arms()
    spec = build_tabletop(config)
    finish(spec, config)
    env = TabletopEnv(xml=spec.to_xml(), n_substeps=10, arms=("left/", "right/"), image_size=None)
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    assert env.action_size(model) == 24
    left, right = (model.body(ArmNames(p).base).id for p in ("left/", "right/"))
    x_left, x_right = data.xmat[left].reshape(3, 3)[:, 0], data.xmat[right].reshape(3, 3)[:, 0]
    np.testing.assert_allclose(x_left, -x_right, atol=1e-9)
    for _ in range(10):
        env.step(model, data, zero_action(2))
    obs = env.observe(model, data)
    assert len(obs["arms"]) == 2
