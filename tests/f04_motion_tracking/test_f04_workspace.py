"""``rle dev`` layout of 04-dance: the public package and the clip, usable on their own."""

import subprocess
import sys
import textwrap

from rle_tasks.f04_motion_tracking.task import PUBLIC_PACKAGE, make_dev_env


def test_workspace_holds_a_self_contained_package_and_the_clip(tmp_path):
    assert make_dev_env(tmp_path, style="dance") is None
    assert (tmp_path / "clips" / "dance.npz").is_file()
    for module in ("g1", "g1_constants", "clip", "env", "tracking", "ppo", "export", "evaluate", "contract"):
        assert (tmp_path / PUBLIC_PACKAGE / f"{module}.py").is_file(), module
    script = textwrap.dedent(
        """
        import numpy as np
        from motion_tracking.clip import Clip
        from motion_tracking.env import TrackingEnv
        from motion_tracking.export import default_meta, linear_policy, open_loop_weights
        from motion_tracking.evaluate import onnx_policy, rollout

        clip = Clip.load("clips/dance.npz")
        env = TrackingEnv(clip)
        obs = env.reset()
        obs, reward, term, trunc, info = env.step(np.zeros(29))
        assert obs.shape == (160,) and np.isfinite(reward)
        meta = default_meta()
        linear_policy("sub", *open_loop_weights(meta), meta)
        policy, meta = onnx_policy("sub")
        r = rollout(policy, meta, clip, seed=0)
        assert 0 < r["survived"] < r["steps"]
        print("ok", r["survived"])
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", script], cwd=tmp_path, capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("ok")
