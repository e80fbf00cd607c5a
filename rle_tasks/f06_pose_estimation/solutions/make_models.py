"""Build the TorchScript baselines of 06-pose-c-learned (committed; rerun to regenerate).

- ``baseline/nan_model/model.pt``: returns NaN (interface gate: non-finite output).
- ``baseline/big_model/model.pt``: a 25 M-element buffer (a stride-0 view of one stored value, so the
  file stays small) beside a working head: refused by the element count before any inference.

    python -m rle_tasks.f06_pose_estimation.solutions.make_models
"""

from __future__ import annotations

from pathlib import Path

import torch

HERE = Path(__file__).resolve().parent


class NanModel(torch.nn.Module):
    def forward(self, rgb: torch.Tensor, depth: torch.Tensor, valid: torch.Tensor) -> torch.Tensor:
        return torch.full((1, 6), float("nan"))


class BigModel(torch.nn.Module):
    def __init__(self) -> None:
        super().__init__()
        self.register_buffer("table", torch.zeros(1).expand(25_000_000))

    def forward(self, rgb: torch.Tensor, depth: torch.Tensor, valid: torch.Tensor) -> torch.Tensor:
        return torch.zeros((1, 6)) + self.table[0]


def main() -> None:
    torch.manual_seed(0)
    torch.jit.save(torch.jit.script(NanModel()), str(HERE / "baseline" / "nan_model" / "model.pt"))
    torch.jit.save(torch.jit.script(BigModel()), str(HERE / "baseline" / "big_model" / "model.pt"))


if __name__ == "__main__":
    main()
