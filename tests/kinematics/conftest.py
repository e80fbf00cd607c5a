"""Shared inline MJCF of the kinematics tests."""

import pytest

_ARM = """
<mujoco>
  <worldbody>
    <body name="a" pos="0.1 0 0.2" quat="0.9238795 0 0.3826834 0">
      <inertial pos="0.05 0.01 0" mass="0.3" diaginertia="1e-3 2e-3 3e-3"/>
      <joint name="j1" axis="0 1 0" pos="0 0 0.02"/>
      <body name="b" pos="0.2 0 0" euler="0.3 0.2 0.1">
        <inertial pos="0.1 0 0.02" quat="0.7 0.7 0 0" mass="0.2" diaginertia="1e-3 1e-3 2e-3"/>
        <joint name="j2" axis="0.3 0.4 0.866"/>
        <body name="c" pos="0.1 0.05 0">
          <inertial pos="0.02 0 0" mass="0.1" diaginertia="1e-4 1e-4 1e-4"/>
          <joint name="j3" axis="1 0 0"/>
        </body>
      </body>
      <body name="d" pos="0 0.1 0">
        <inertial pos="0 0.03 0" mass="0.05" diaginertia="1e-5 1e-5 1e-5"/>
        <joint name="j4" axis="0 0 1"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture
def branching_arm_xml() -> str:
    """Four hinges on a branching tree with body, joint and inertial offsets and a tilted axis."""
    return _ARM
