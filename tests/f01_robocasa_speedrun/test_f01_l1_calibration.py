"""L1 camera self-calibration (``agents/calibrate_l1``) against the model's cameras, and the L1 door
perception (``agents/perceive_l1``) against the world state.

One L3 session with images (its observation carries the true ``cameras`` and the fixtures): the hand
calibrates the agent views in pretrain kitchen 0, then the fridge door is perceived from depth alone in
pretrain kitchens 0-2. Measured (2-core machine): focal length 110.3-110.4 px (true 110.85), camera
position 13 mm, orientation 10-14 mrad, reprojection rms 1.1-1.2 px; scene points in front of the robot
(depth < 1.6 m) 15 mm (median); 317 actions; handle within 10 mm, hinge within 6 mm.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.envs.kitchen.harness.geometry import deproject, quat_to_mat, world_from_base
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot
from rle_tasks.f01_robocasa_speedrun.solutions.agents import Direct
from rle_tasks.f01_robocasa_speedrun.solutions.agents.calibrate_l1 import AGENT_VIEWS, calibrate
from rle_tasks.f01_robocasa_speedrun.solutions.agents.perceive_l1 import door
from rle_tasks.f01_robocasa_speedrun.task import KITCHEN_TASKS, scenes

pytestmark = [pytest.mark.physics, pytest.mark.render]


@pytest.fixture(scope="module")
def calibrated():
    kitchen = next(k for k in KITCHEN_TASKS if k.task == "OpenFridge")
    sc = scenes(kitchen, 3, Secret(PUBLIC_KEY, public=True), image_size=(128, 128))
    session = sc.open_session(task_id=kitchen.task_id(3), budget=None)
    robot = Robot(Direct(session))
    motion = Motion(robot)
    robot.reset(kitchen=0, seed=0)
    return robot, motion, calibrate(robot, motion)


def test_calibration_matches_the_model_cameras(calibrated):
    robot, _, cal = calibrated
    obs = robot.observe()
    base_from_world = np.linalg.inv(world_from_base(obs))
    assert cal.steps < 400
    for cam in AGENT_VIEWS:
        k_true = np.asarray(obs["cameras"][cam]["K"])
        b_true = base_from_world @ np.asarray(obs["cameras"][cam]["world_from_camera"])
        k, b = cal.K[cam], cal.base_from_camera[cam]
        assert abs(k[0, 0] - k_true[0, 0]) / k_true[0, 0] < 0.02, (cam, k[0, 0])
        assert np.linalg.norm(b[:3, 3] - b_true[:3, 3]) < 0.025, (cam, b[:3, 3] - b_true[:3, 3])
        angle = np.linalg.norm(Rotation.from_matrix(b[:3, :3].T @ b_true[:3, :3]).as_rotvec())
        assert angle < 0.025, (cam, angle)
        assert cal.rms[cam] < 2.0, (cam, cal.rms[cam])
        # what the programs use: the scene's points in front of the robot
        d = np.asarray(obs["depth"][cam], np.float32)
        p_true, p_est = deproject(d, k_true), deproject(d, k)
        w_true = p_true @ b_true[:3, :3].T + b_true[:3, 3]
        w_est = p_est @ b[:3, :3].T + b[:3, 3]
        near = (p_true[:, 2] < 1.6) & (w_true[:, 0] > 0.45)
        err = np.linalg.norm(w_est - w_true, axis=1)[near]
        assert np.median(err) < 0.025, (cam, np.median(err))


@pytest.mark.parametrize("k", [0, 1, 2])
def test_fridge_door_from_depth(calibrated, k):
    robot, motion, cal = calibrated
    obs = robot.reset(kitchen=k, seed=k)
    f = obs["fixtures"][obs["target"]["fixture"]]
    est = door(robot, cal, (1.0, 1.7), motion)
    assert est is not None
    out = quat_to_mat(f["door_quat"]) @ np.array([0.0, -1.0, 0.0])
    handle = np.asarray(f["sites"]["handle"])
    assert np.linalg.norm(est.handle[:2] - handle[:2]) < 0.02, (est.handle, handle)
    assert np.linalg.norm(est.hinge[:2] - np.asarray(f["door_pos"])[:2]) < 0.03, (est.hinge, f["door_pos"])
    assert float(np.dot(est.out, out)) > 0.99
