"""Control: operational-space control on MuJoCo Jacobians, the 12-D action layout, a metered tabletop
environment and a Cartesian movement helper.

Interface (what tasks and agents use):

- ``layout``: one arm's action is 12 numbers in [-1, 1]: tool-site delta pose in the robot base frame
  (``[dx, dy, dz]`` x ``POS_STEP`` = 0.02 m, ``[drx, dry, drz]`` x ``ROT_STEP`` = 0.1 rad), gripper
  (-1 open, +1 closed), base (3), torso (1), mode (1) inert for fixed arms; ``12 n`` for ``n`` arms.
- ``OperationalSpaceController(model, site, joints, motors, home)``: ``torques(data, pos, quat)``.
- ``TabletopEnv(xml=..., n_substeps=..., arms=(prefix, ...))``: a ``MeteredEnv`` over a scene of
  ``rle_design.scene.tabletop``; ``step`` maps one action to target poses and gripper commands and
  runs the OSC every physics step; targets live in mocap bodies (resets and replays restore them).
- ``CartesianHelper(step, obs)``: ``move_to(pos, quat)``, ``grasp()``, ``release()``, ``wait(n)``;
  it only calls ``step(action)``, so with a ``LedgerClient`` every motion is a metered action.
  ``ArmGroup(step, obs, n_arms)`` gives one helper per arm of the same session; an arm holding a
  part keeps its gripper command while another moves.
- ``WholeBodyQP(model, joints, effort, contacts, reference)`` (``wbc``): whole-body QP of a floating-base
  robot on position servos (MuJoCo dynamics, OSQP): ``solve(qpos, qvel, frame, stance)`` gives
  accelerations, torques and contact forces in friction pyramids tracking a ``motion_reference``
  (``wbc_reference``) with the task weights and gains of ``wbc_tasks``; ``servo_targets`` turns the
  torques into PD targets.
- ``replay(env, ledger_path)``: rebuilds the final state of a ledger's session by replaying its
  recorded resets and actions on the same environment definition (``replay.other_scene`` when the
  ledger's model digest differs, ``replay.diverged`` when the simulation time does not match).

Replays are exact only for the same scene, controller and MuJoCo build: a change to the tabletop
scene, ``TabletopEnv.step`` or ``OperationalSpaceController`` changes what recorded actions do, so
committed ledgers must then be regenerated. ``TabletopEnv.fingerprint`` hashes the MJCF with mesh
files replaced by their content digests, so a ledger replays on any checkout.
"""

from rle_design.control.env import LEASH, TabletopEnv, free_body_poses
from rle_design.control.helper import ArmGroup, CartesianHelper, MoveResult
from rle_design.control.layout import ACTION_SIZE, POS_STEP, ROT_STEP, gripper_action, zero_action
from rle_design.control.osc import OperationalSpaceController, OscGains, orientation_error
from rle_design.control.replay import ReplayError, replay
from rle_design.control.wbc import WholeBodyQP, servo_targets
from rle_design.control.wbc_reference import motion_reference

__all__ = [
    "ACTION_SIZE",
    "LEASH",
    "POS_STEP",
    "ROT_STEP",
    "ArmGroup",
    "CartesianHelper",
    "MoveResult",
    "OperationalSpaceController",
    "OscGains",
    "ReplayError",
    "TabletopEnv",
    "WholeBodyQP",
    "free_body_poses",
    "gripper_action",
    "motion_reference",
    "orientation_error",
    "replay",
    "servo_targets",
    "zero_action",
]
