"""Closed forms of the workcell: bracket mass, the magnet's holding threshold, the belt's speed, the nest."""

import mujoco
import pytest

from rle_design.scene import AdhesionActuator
from rle_tasks.f07_bin_clearing.public.env import NestLogic, nest_members
from rle_tasks.f07_bin_clearing.public.workcell import (
    BELT_SPEED,
    BELT_TOP,
    BELT_Y,
    BRACKET_MASS,
    GROUP_PART,
    MAGNET_GAIN,
    MAGNET_GAIN_WEIGHTS,
    MAGNET_PAD,
    NAMES,
    NEST_X,
    PROXY_T,
    STEEL_DENSITY,
    add_bracket,
    build_workcell,
)

G = 9.81


def test_bracket_mass_is_density_times_volume():
    # web 60 x 25 x 2 mm + two flanges 30 x 25 x 2 mm = 6000 mm^3; m = 7850 kg/m^3 x 6e-6 m^3 = 47.1 g
    m = build_workcell(1).compile()
    assert m.body_mass[m.body(NAMES.part(0)).id] == pytest.approx(STEEL_DENSITY * 6000e-9, rel=1e-9)
    assert pytest.approx(0.0471, rel=1e-9) == BRACKET_MASS


def _hang(gain_n: float, touching: bool = True) -> float:
    """Height of a bracket hanging under a fixed magnet pad after 2 s [m]."""
    s = mujoco.MjSpec()
    s.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    s.option.o_solref = [0.005, 1.0]
    mag = s.worldbody.add_body(name="magnet", pos=[0, 0, 0.5])
    pad = mag.add_geom(
        name="pad", type=mujoco.mjtGeom.mjGEOM_BOX, size=[MAGNET_PAD[0], MAGNET_PAD[0], MAGNET_PAD[1]]
    )
    pad.contype = pad.conaffinity = GROUP_PART
    gap = -0.0002 if touching else 0.002
    add_bracket(s, 0, (0, 0, 0.5 - MAGNET_PAD[1] - PROXY_T - gap))
    AdhesionActuator("magnet", "magnet", gain_n).edit_spec(s)
    m = s.compile()
    d = mujoco.MjData(m)
    d.ctrl[0] = 1.0
    mujoco.mj_step(m, d, 1000)
    return float(d.xpos[m.body(NAMES.part(0)).id][2])


@pytest.mark.physics
def test_magnet_holds_exactly_above_the_part_weight():
    w = BRACKET_MASS * G
    assert pytest.approx(MAGNET_GAIN_WEIGHTS * w) == MAGNET_GAIN
    start = 0.5 - MAGNET_PAD[1] - PROXY_T + 0.0002
    assert _hang(MAGNET_GAIN) == pytest.approx(start, abs=0.002)  # documented gain: 10 m g holds
    assert _hang(1.05 * w) == pytest.approx(start, abs=0.002)  # just above m g holds
    assert _hang(0.95 * w) < start - 1.0  # just below m g: it falls away
    assert _hang(MAGNET_GAIN, touching=False) < start - 1.0  # no contact, no pull


def _cell_with_part_at(x: float, n: int = 1) -> tuple[mujoco.MjModel, mujoco.MjData]:
    m = build_workcell(n).compile()
    d = mujoco.MjData(m)
    for i in range(n):
        adr = m.jnt_qposadr[m.body(NAMES.part(i)).jntadr[0]]
        d.qpos[adr : adr + 3] = (x + 0.07 * i, BELT_Y, BELT_TOP + 0.001 + 0.035 * i)
        d.qpos[adr + 3 : adr + 7] = (1, 0, 0, 0)
    mujoco.mj_forward(m, d)
    return m, d


@pytest.mark.physics
def test_belt_carries_a_part_at_its_surface_speed():
    m, d = _cell_with_part_at(0.50)
    body = m.body(NAMES.part(0)).id
    mujoco.mj_step(m, d, 250)  # 0.5 s to pick up speed
    x0, t0 = d.xipos[body][0], d.time
    mujoco.mj_step(m, d, 500)  # 1 s
    v = (d.xipos[body][0] - x0) / (d.time - t0)
    assert v == pytest.approx(BELT_SPEED, rel=0.05)


@pytest.mark.physics
def test_nest_releases_one_part_and_blocks_on_two():
    for n, released in ((1, True), (2, False)):
        m, d = _cell_with_part_at(NEST_X[0] + 0.035, n)
        logic = NestLogic(m, n)
        members = []
        for _ in range(60):  # 3 s of 50 ms periods
            mujoco.mj_step(m, d, 25)
            logic.update(m, d)
            members.append(len(nest_members(m, d, n)))
        assert max(members) == n
        assert (min(members) < n) is released, f"{n} part(s) in the nest"
        if not released:
            assert d.userdata[1] == 0.0  # gate stayed closed


def test_adhesion_actuator_config_checks_gain_and_body():
    from rle_design.errors import ConfigError, MissingElement

    with pytest.raises(ConfigError):
        AdhesionActuator("magnet", "magnet", 0.0).validate()
    with pytest.raises(MissingElement):
        AdhesionActuator("magnet", "no_such_body", 1.0).edit_spec(mujoco.MjSpec())
    s = mujoco.MjSpec()
    s.worldbody.add_body(name="pad").add_geom(size=[0.01, 0, 0])
    AdhesionActuator("magnet", "pad", 2.5).edit_spec(s)
    m = s.compile()
    assert m.actuator_gainprm[0, 0] == pytest.approx(2.5) and tuple(m.actuator_ctrlrange[0]) == (0.0, 1.0)
