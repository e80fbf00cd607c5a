"""A camera that stands for a real one sees geoms only: site markers are not drawn with sites=False."""

import mujoco
import numpy as np

from rle_design.sensors.rgbd import RgbdSensor

XML = """
<mujoco>
  <visual><global offwidth="64" offheight="64"/></visual>
  <worldbody>
    <camera name="cam" pos="0 0 1" xyaxes="1 0 0 0 1 0"/>
    <geom type="plane" size="1 1 0.1" rgba="0 0 1 1"/>
    <site name="marker" pos="0 0 0.3" size="0.2" rgba="1 0 0 1"/>
  </worldbody>
</mujoco>
"""


def test_sites_are_drawn_only_when_asked():
    model = mujoco.MjModel.from_xml_string(XML)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    centre = {}
    for sites in (True, False):
        with RgbdSensor(model, "cam", 64, 64, segmentation=False, sites=sites) as cam:
            centre[sites] = cam.render(data).rgb[32, 32].astype(int)
    assert centre[True][0] > 150 and centre[True][2] < 100  # the red marker sphere
    assert centre[False][2] > 150 and centre[False][0] < 100  # the blue floor behind it
    assert not np.array_equal(centre[True], centre[False])
