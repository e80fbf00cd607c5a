"""Noise models: depth sigma = k z^2, dropout rate, RGB noise; all reproducible from a Generator."""

import numpy as np
import pytest

from rle_design.errors import RleError
from rle_design.sensors import CameraIntrinsics, CameraSpec, DepthNoise, Frame, RgbNoise, add_noise


def _frame(z: float = 2.0, n: int = 200) -> Frame:
    cam = CameraSpec("c", 0, CameraIntrinsics.from_fovy(45.0, n, n), np.eye(4), 0.01, 50.0)
    depth = np.full((n, n), z, np.float32)
    valid = np.ones((n, n), bool)
    valid[:, :10] = False
    return Frame(np.full((n, n, 3), 128, np.uint8), depth, None, valid, cam)


def test_depth_noise_std_grows_with_z_squared():
    noise = DepthNoise(k=2e-3)
    for z in (0.5, 2.0):
        f = add_noise(_frame(z), np.random.default_rng(1), depth=noise)
        err = f.depth[f.valid] - z
        # sigma(z) = k z^2; 38000 samples give the std to ~0.4 % (1 sigma), test at 3 %.
        assert err.std() == pytest.approx(2e-3 * z**2, rel=0.03)
        assert abs(err.mean()) < 4 * 2e-3 * z**2 / np.sqrt(err.size)
        assert np.all(f.depth[:, :10] == z)  # invalid pixels untouched


def test_dropout_rate_and_mask():
    f = add_noise(_frame(), np.random.default_rng(2), depth=DepthNoise(k=0.0, dropout=0.1))
    n_valid = 200 * 190
    dropped = n_valid - f.valid.sum()
    # Binomial(n, 0.1): std = sqrt(n p (1-p)) ~ 58; allow 5 std.
    assert abs(dropped - 0.1 * n_valid) < 5 * np.sqrt(n_valid * 0.09)
    assert np.all(f.depth[:, 10:][~f.valid[:, 10:]] == 0.0)


def test_rgb_noise_is_clipped_and_reproducible():
    a = add_noise(_frame(), np.random.default_rng(3), rgb=RgbNoise(sigma=5.0))
    b = add_noise(_frame(), np.random.default_rng(3), rgb=RgbNoise(sigma=5.0))
    assert a.rgb.dtype == np.uint8
    assert np.array_equal(a.rgb, b.rgb)
    assert (a.rgb.astype(float) - 128).std() == pytest.approx(5.0, rel=0.03)
    f4 = _frame(n=4)
    white = Frame(np.full((4, 4, 3), 255, np.uint8), f4.depth, None, f4.valid, f4.camera)
    assert add_noise(white, np.random.default_rng(0), rgb=RgbNoise(50.0)).rgb.max() == 255


def test_invalid_parameters_raise():
    with pytest.raises(RleError, match=r"noise parameter dropout=1.5 must be finite and \[0, 1.0\]"):
        DepthNoise(dropout=1.5)
    with pytest.raises(RleError, match="noise parameter sigma=-1.0 must be finite and >= 0"):
        RgbNoise(sigma=-1.0)
