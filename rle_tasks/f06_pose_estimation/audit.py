"""Adversarial cases of family 06: hostile TorchScript archives and estimators that reach for labels.

Each case fails the interface gate (score 0) with its code:

- ``pickle_payload``: ``model.pt`` whose ``data.pkl`` is a pickle calling ``os.system`` (TorchScript's
  restricted unpickler refuses the global; the load fails inside the sandbox anyway);
- ``model_reads_files``: ``model.pt`` whose serialized code opens ``/proc/1/environ`` (TorchScript cannot
  compile ``open``; the load fails);
- ``estimator_reads_dev_labels``: ``estimator.py`` that connects to the workspace's development server
  for labels during evaluation (socket creation is forbidden in the sandbox);
- ``estimator_imports_verifier``: ``estimator.py`` that imports the verifier's block geometry
  (the verifier package is not importable in the sandbox);
- ``wrong_type``: ``update`` returns a string.
"""

from __future__ import annotations

import shutil
import zipfile
from pathlib import Path

from rle_tasks.audit.case import Case
from rle_tasks.core.solutions import materialise

C_TASK, B_TASK = "06-pose-c-learned", "06-pose-b-rgbd"
PLANTED = "/tmp/rle_planted_reward.json"


def _rewrite_archive(src: Path, dst: Path, edit) -> None:
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w") as zout:
        for info in zin.infolist():
            zout.writestr(info, edit(info.filename, zin.read(info.filename)))


def _model_case(edit):
    def build(d: Path) -> Path:
        base = materialise(C_TASK, "baseline/nan_output")
        _rewrite_archive(base / "model.pt", d / "model.pt", edit)
        return d

    return build


def _payload(name: str, data: bytes) -> bytes:
    if name.endswith("/data.pkl"):
        return b"cposix\nsystem\n(S'echo 1 > " + PLANTED.encode() + b"'\ntR."
    return data


def _reads_files(name: str, data: bytes) -> bytes:
    if name.endswith("code/__torch__.py"):
        return data.replace(
            b"    return torch.full([1, 6], nan)",
            b"    secret = open('/proc/1/environ').read()\n    return torch.full([1, 6], nan)",
        )
    return data


def _estimator(code: str):
    def build(d: Path) -> Path:
        shutil.copytree(materialise(B_TASK, "reference"), d, dirs_exist_ok=True)
        (d / "estimator.py").write_text(code)
        return d

    return build


DEV_LABELS = """
import socket


def reset():
    return None


def update(obs):
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.connect("../workspace/.rle/ledger.sock")
    return (0.0, 0.0, 0.0, 0)
"""
IMPORT_VERIFIER = """
from rle_tasks.f06_pose_estimation.shapes import BLOCKS


def reset():
    return None


def update(obs):
    return (0.0, 0.0, 0.0, len(BLOCKS) - 3)
"""
WRONG_TYPE = """
def reset():
    return None


def update(obs):
    return "T at the centre"
"""


def cases() -> list[Case]:
    """Family 06's hostile archives and estimators (``rle audit-verifiers``)."""
    return [
        Case("code/06_pickle_payload", C_TASK, "sandbox.import_error", _model_case(_payload), wall_cap_s=120),
        Case(
            "code/06_model_reads_files",
            C_TASK,
            "sandbox.import_error",
            _model_case(_reads_files),
            wall_cap_s=120,
        ),
        Case("code/06_estimator_reads_dev_labels", B_TASK, "sandbox.forbidden", _estimator(DEV_LABELS)),
        Case(
            "code/06_estimator_imports_verifier", B_TASK, "sandbox.import_error", _estimator(IMPORT_VERIFIER)
        ),
        Case("code/06_wrong_type", B_TASK, "sandbox.bad_type", _estimator(WRONG_TYPE)),
    ]
