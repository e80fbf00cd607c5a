"""The wrist F/T reads what a real sensor above a contact magnet reads: a held part adds its weight.

Closed form: a bracket of mass m held still under the pad changes the reading by m g straight up in
world axes (m = 7850 kg/m^3 x (0.060 x 0.025 + 2 x 0.030 x 0.025) m^2 x 0.002 m = 0.0471 kg, m g =
0.462 N). Without the adhesion reaction the sensor would see only the contact's push on the pad
(adhesion gain 4.62 N minus the weight: 4.16 N the other way), the 4-7 N a user measured.
"""

import mujoco
import numpy as np
import pytest

from rle_design.sensors import ft_reading
from rle_tasks.f07_bin_clearing.public.env import held_contact, make_env
from rle_tasks.f07_bin_clearing.public.pile import PileSpec
from rle_tasks.f07_bin_clearing.public.workcell import BRACKET_MASS, HOME, MAGNET_GAIN, NAMES, G


@pytest.fixture(scope="module")
def held():
    env = make_env(PileSpec.public(101))
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    site = model.site(NAMES.ft_site).id

    def hold(ticks: int, magnet: float) -> None:
        for _ in range(ticks):
            env.step(model, data, np.concatenate([HOME, [magnet]]))

    hold(40, 0.0)
    tare = env.observe(model, data)["ft"].copy()
    pad = model.geom(NAMES.magnet_pad).id
    part = model.body(NAMES.part(0))
    qadr, dadr = model.jnt_qposadr[part.jntadr[0]], model.jnt_dofadr[part.jntadr[0]]
    data.qpos[qadr : qadr + 3] = data.geom_xpos[pad] - [0.0, 0.0, model.geom_size[pad][2] + 0.002]
    data.qpos[qadr + 3 : qadr + 7] = [1.0, 0.0, 0.0, 0.0]
    data.qvel[dadr : dadr + 6] = 0.0
    mujoco.mj_forward(model, data)
    hold(60, 1.0)
    rot = data.site_xmat[site].reshape(3, 3)
    return {
        "model": model,
        "data": data,
        "rot": rot,
        "tare": tare,
        "obs": env.observe(model, data)["ft"].copy(),
        "raw": ft_reading(model, data, NAMES.force, NAMES.torque),
        "speed": float(np.linalg.norm(data.cvel[part.id])),
    }


def test_a_held_part_reads_its_weight(held):
    assert held_contact(held["model"], held["data"]) and held["speed"] < 1e-3  # held, still
    delta = held["rot"] @ (held["obs"] - held["tare"])[:3]  # world axes: the parent's extra support
    assert delta[2] == pytest.approx(BRACKET_MASS * G, abs=2e-3)  # m g = 0.462 N, up
    assert np.linalg.norm(delta[:2]) < 0.02


def test_without_the_reaction_the_sensor_sees_the_contact_push_only(held):
    delta = held["rot"] @ (held["raw"] - held["tare"])[:3]
    assert delta[2] == pytest.approx(-(MAGNET_GAIN - BRACKET_MASS * G), abs=5e-3)  # -4.16 N


def test_the_correction_vanishes_with_the_magnet_off(held):
    model, data = held["model"], held["data"]
    site = model.site(NAMES.ft_site).id
    from rle_design.sensors.force_torque import adhesion_reaction

    saved = data.ctrl[7]
    data.ctrl[7] = 0.0
    mujoco.mj_forward(model, data)
    assert np.allclose(adhesion_reaction(model, data, site), 0.0)
    data.ctrl[7] = saved
    mujoco.mj_forward(model, data)
