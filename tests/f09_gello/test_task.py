"""Development environment, public helpers and the trim protocol of 09-gello."""

import numpy as np

from rle_design.sandbox import ParticipantFault
from rle_tasks.core.registry import get_task
from rle_tasks.core.solutions import materialise
from rle_tasks.f09_gello.device import ASSET_DIR
from rle_tasks.f09_gello.public.gello_helpers import HOME, load_leader, peak_torque, residual, workspace_grid
from rle_tasks.f09_gello.submission import load_submission
from rle_tasks.f09_gello.trim_runner import TrimRunner


def test_dev_env_lays_out_leaders_helpers_and_a_valid_skeleton(tmp_path):
    get_task("09-gello").make_dev_env(tmp_path)
    for robot in ("panda", "ur5e", "xarm7"):
        assert (tmp_path / "leaders" / robot / "lead.xml").read_text() == (
            ASSET_DIR / robot / "lead.xml"
        ).read_text()
        assert load_submission(robot, tmp_path / "submission" / robot).usable
    assert (tmp_path / "gello_helpers.py").exists() and (tmp_path / "example_trim.py").exists()
    text = (tmp_path / "instruction.md").read_text()
    assert "2.30 kg" in text and "noslip" in text and "secret" not in text.lower()


def test_workspace_grid_is_inside_the_limits_and_reproducible():
    ranges = np.array([[-1.0, 1.0], [0.0, 2.0]])
    grid = workspace_grid(ranges, 500)
    assert np.all(grid >= ranges[:, 0] + 0.1) and np.all(grid <= ranges[:, 1] - 0.1)
    assert np.array_equal(grid, workspace_grid(ranges, 500))


def test_home_poses_are_inside_the_limits_and_residual_helpers_agree():
    for robot, home in HOME.items():
        m, km, springs = load_leader(ASSET_DIR / robot / "lead.xml")
        assert np.all((m.jnt_range[:, 0] <= home) & (np.array(home) <= m.jnt_range[:, 1]))
        assert residual(km, springs, np.array(home)[None]).shape == (1, m.nv)
        assert peak_torque(km, springs, m.jnt_range, n=256)[1] > 0.7  # shoulder sags


def test_trim_runner_records_faults_and_returns_none(tmp_path):
    (tmp_path / "trim.py").write_text(
        "import numpy as np\n"
        "def plan_probe():\n    return np.zeros((14, 6))\n"
        "def adapt(probes):\n    raise ValueError('bad probes')\n"
        "def feedforward(q, params=None):\n    return np.full(6, np.nan)\n"
    )
    ranges = np.tile([-1.0, 1.0], (6, 1))
    with TrimRunner(tmp_path / "trim.py", 6) as trim:
        assert trim.plan(ranges) is None
        assert trim.adapt("submitted", np.zeros((16, 6)), np.zeros((16, 6))) is None
        assert trim.feedforward(np.zeros(6), None) is None
    assert [f.code for f in trim.faults] == ["sandbox.bad_shape", "sandbox.exception", "sandbox.non_finite"]
    assert all(isinstance(f, ParticipantFault) for f in trim.faults)


def test_reference_trim_recovers_a_hidden_copy_within_the_friction_band():
    from rle_tasks.core.runtime.secrets import load_secret
    from rle_tasks.f09_gello import battery, device, measurements

    robot = "ur5e"
    sub = load_submission(robot, materialise(get_task("09-gello"), "reference") / robot)
    rng = np.random.default_rng(0)
    dev = device.apply_variation(sub.model, device.draw_variation(rng, 6))
    poses = workspace_grid(sub.model.jnt_range, 5, seed=3)
    with TrimRunner(sub.design.root / "trim.py", 6) as trim:
        plan = trim.plan(sub.model.jnt_range)
        ff = measurements._adapted_ff(trim, plan, "submitted", dev, np.array(HOME[robot]), poses, rng)
    assert not trim.faults and load_secret().public
    err = np.abs(battery.residual_mujoco(dev, poses) - ff)
    assert err.max() < sub.model.dof_frictionloss[0]  # holds: below the 0.0128 N m friction
    assert np.abs(battery.residual_mujoco(dev, poses)).max() > 0.02  # the copy really is unbalanced
