"""Universal Robots UR5e (robosuite 1.5.2 ``ur5e/robot.xml``) constants."""

from __future__ import annotations

from rle_design.scene.robots.constants import RobotConstants

UR5E = RobotConstants(
    id="ur5e",
    joints=(
        "shoulder_pan_joint",
        "shoulder_lift_joint",
        "elbow_joint",
        "wrist_1_joint",
        "wrist_2_joint",
        "wrist_3_joint",
    ),
    home=(0.0, -1.571, 1.571, -1.571, -1.571, 0.0),
    stowed=(-0.470, -1.735, 2.480, -2.275, -1.590, -1.991),
    actuators=tuple(f"torq_j{i}" for i in range(1, 7)),
    torque_limits=(150.0, 150.0, 150.0, 28.0, 28.0, 28.0),
    source="home: upper arm vertical, forearm level, wrists at -90 deg; stowed: robosuite init_qpos; limits: robosuite motor ctrlrange",
)
