import urllib.request

import numpy as np
import pytest
from PIL import Image

from rle_design.errors import RleError
from rle_design.scene import arm_ids
from rle_design.viz.preview import load_preview_model, preview, serve_meshcat, settle_pose
from rle_design.viz.render import render_image
from rle_tasks.cli import main
from rle_tasks.demo import TEST_BASE

pytestmark = pytest.mark.render


@pytest.mark.parametrize("arm", arm_ids())
def test_cli_preview_png_shows_the_arm(arm, tmp_path):
    out = tmp_path / f"{arm}.png"
    assert main(["preview", str(TEST_BASE), "--arm", arm, "--png", str(out)]) == 0
    img = np.asarray(Image.open(out).convert("RGB")).astype(int)
    assert img.shape == (360, 3 * 480, 3)
    # The arm is visible: compared with the bare base from the same camera (which renders identically
    # twice), a sizeable region changes (the slender xArm7 covers ~1.8 % of this view, the Panda ~5 %).
    bare = load_preview_model(TEST_BASE)
    with_arm = load_preview_model(TEST_BASE, arm=arm, mount_site="arm_mount_site")
    kw = dict(width=240, height=180, lookat=[0.0, 0.0, 0.6], distance=2.5, azimuth=180.0, elevation=-15.0)
    a = render_image(bare, settle_pose(bare), **kw).astype(int)
    b = render_image(with_arm, settle_pose(with_arm), **kw).astype(int)
    changed = (np.abs(a - b).sum(-1) > 60).mean()
    assert changed > 0.01, f"only {changed:.3%} of pixels show the {arm}"


def test_preview_missing_file_is_clear(tmp_path):
    with pytest.raises(RleError, match="does not exist"):
        preview(tmp_path / "nope.xml", png=tmp_path / "x.png")


def test_meshcat_serves_a_page():
    pytest.importorskip("meshcat", reason="viz extra not installed")
    model = load_preview_model(TEST_BASE, arm="xarm7", mount_site="arm_mount_site")
    url = serve_meshcat(model, settle_pose(model), block=False)
    with urllib.request.urlopen(url, timeout=10) as resp:
        assert resp.status == 200
        assert b"meshcat" in resp.read().lower()
