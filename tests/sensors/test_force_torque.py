"""Force/torque sensors against a hanging mass: F = m g, tau = r_c x F (closed form)."""

import mujoco
import numpy as np
import pytest

from rle_design.errors import MissingElement, RleError
from rle_design.sensors import ft_reading

G = 9.81
MASS = 2.5
COM = np.array([0.05, 0.0, -0.05])  # load centre of mass relative to the sensor site [m]

XML = f"""
<mujoco>
  <option gravity="0 0 -{G}"/>
  <worldbody>
    <body name="hook" pos="0 0 1">
      <geom type="box" size="0.01 0.01 0.01" mass="0.1"/>
      <body name="load" pos="0 0 -0.1">
        <site name="ft_site"/>
        <site name="ft_rot" euler="90 0 0"/>
        <geom type="sphere" size="0.02" pos="{COM[0]} {COM[1]} {COM[2]}" mass="{MASS}"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <force name="f" site="ft_site"/>
    <torque name="t" site="ft_site"/>
    <force name="f_rot" site="ft_rot"/>
    <torque name="t_rot" site="ft_rot"/>
    <framepos name="p" objtype="site" objname="ft_site"/>
  </sensor>
</mujoco>
"""


@pytest.fixture(scope="module")
def model_data():
    m = mujoco.MjModel.from_xml_string(XML)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    return m, d


def test_hanging_mass_reads_weight_and_moment(model_data):
    m, d = model_data
    w = ft_reading(m, d, "f", "t")
    assert w.shape == (6,)
    # The parent holds the load at rest: F = m g up (+z), torque about the site tau = r_c x F.
    force = np.array([0.0, 0.0, MASS * G])
    torque = np.cross(COM, force)  # = (0, -m g x_c, 0)
    assert np.allclose(w[:3], force, atol=1e-9)
    assert np.allclose(w[3:], torque, atol=1e-9)


def test_rotated_site_reads_in_its_frame_and_world_option_rotates_back(model_data):
    m, d = model_data
    local = ft_reading(m, d, "f_rot", "t_rot")
    # Site rotated +90 deg about x: its y axis is R[:, 1] = (0, cos 90, sin 90) = world +z.
    assert np.allclose(local[:3], [0.0, MASS * G, 0.0], atol=1e-9)
    world = ft_reading(m, d, "f_rot", "t_rot", frame="world")
    assert np.allclose(world[:3], [0.0, 0.0, MASS * G], atol=1e-9)
    assert np.allclose(world[3:], np.cross(COM, [0.0, 0.0, MASS * G]), atol=1e-9)


def test_unknown_and_wrong_sensors_are_named(model_data):
    m, d = model_data
    with pytest.raises(MissingElement) as exc:
        ft_reading(m, d, "wrist_force", "t")
    assert str(exc.value) == "force sensor 'wrist_force' does not exist. Available force sensors: f, f_rot"
    with pytest.raises(RleError) as exc2:
        ft_reading(m, d, "f", "p")
    assert str(exc2.value) == "sensor 'p' is not a torque sensor. Available torque sensors: t, t_rot"
    with pytest.raises(RleError, match="frame 'body' is unknown. Available frames: site, world"):
        ft_reading(m, d, "f", "t", frame="body")


MAGNET = """
<mujoco>
  <option timestep="0.001"/>
  <worldbody>
    <body name="tool" pos="0 0 1">
      <site name="ft"/>
      <geom name="pad" type="box" size="0.05 0.05 0.01" pos="0 0 -0.05" mass="0.5"/>
    </body>
    <body name="part" pos="0.01 0.02 {z}">
      <freejoint/>
      <geom type="box" size="0.02 0.02 0.01" mass="{mass}"/>
    </body>
  </worldbody>
  <actuator><adhesion name="magnet" body="tool" gain="{gain}" ctrlrange="0 1"/></actuator>
  <sensor><force name="f" site="ft"/><torque name="t" site="ft"/></sensor>
</mujoco>
"""


def test_adhesion_reaction_makes_a_held_part_read_its_weight():
    """A part of mass m held under a fixed tool by an adhesion actuator of gain k: the raw sensor sees
    the pad's contact push, k - m g, downward; with the reaction the reading grows by m g upward, and
    the torque about the site by (r x m g) for the part's offset r."""
    m, k = 0.2, 30.0
    model = mujoco.MjModel.from_xml_string(MAGNET.format(z=1 - 0.05 - 0.01 - 0.01 + 5e-4, mass=m, gain=k))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    empty = ft_reading(model, data, "f", "t", frame="world")  # the tool's own weight: 0.5 g up
    data.ctrl[0] = 1.0
    for _ in range(2000):
        mujoco.mj_step(model, data)
    assert np.linalg.norm(data.qvel) < 1e-4  # held still
    raw = ft_reading(model, data, "f", "t", frame="world") - empty
    full = ft_reading(model, data, "f", "t", frame="world", adhesion=True) - empty
    g = 9.81
    assert raw[2] == pytest.approx(-(k - m * g), rel=1e-3)
    assert full[2] == pytest.approx(m * g, rel=1e-4)
    r = data.xipos[model.body("part").id] - data.site_xpos[0]
    assert full[3:] == pytest.approx(-np.cross(r, [0.0, 0.0, -m * g]), abs=1e-4)  # holds the weight at r
