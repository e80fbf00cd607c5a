"""docs/adding-a-family.md: its worked example, written out as it stands, is a working family."""

import re
import sys
from pathlib import Path

import pytest
import yaml

from rle_tasks.core import families as families_mod
from rle_tasks.core import registry
from rle_tasks.core.report import artifact_sha256
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import build, declaration, materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.core.verify import run_verify

DOC = Path(__file__).resolve().parents[2] / "docs" / "adding-a-family.md"
BLOCK = re.compile(r"`(f10_box_tip/[^`]+)`.*?\n```[a-z]*\n(.*?)```", re.DOTALL)


def _write_family(text: str, files: list[tuple[str, str]], root: Path, monkeypatch) -> None:
    """Write the page's files under ``root`` (with the family's ``assets/``) and register the family with
    the first data line of ``text``; the cache goes to ``root/cache``."""
    for rel, body in files:
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(body)
    (root / files[0][0].split("/")[0] / "assets").mkdir()
    line = yaml.safe_load(re.search(r"```yaml\n(.*?)```", text, re.DOTALL).group(1))[0]
    info = families_mod.FamilyInfo(line["number"], line["slug"], line["workflow"], line["title"])
    known = families_mod.families()
    monkeypatch.setattr(families_mod, "families", lambda: (*known, info))
    monkeypatch.syspath_prepend(str(root))
    monkeypatch.setenv("RLE_CACHE_DIR", str(root / "cache"))


@pytest.fixture
def example(tmp_path, monkeypatch):
    """The example family written to ``tmp_path`` and registered with the page's data line."""
    text = DOC.read_text()
    files = BLOCK.findall(text)
    assert [f for f, _ in files] == [
        "f10_box_tip/__init__.py",
        "f10_box_tip/task.py",
        "f10_box_tip/instruction.md",
        "f10_box_tip/scoring.py",
        "f10_box_tip/verifier.py",
        "f10_box_tip/solutions/__init__.py",
        "f10_box_tip/solutions/reference/box.xml",
    ]
    _write_family(text, files, tmp_path, monkeypatch)
    yield tmp_path
    for name in [m for m in sys.modules if m.startswith("f10_box_tip")]:
        del sys.modules[name]


def _task(root: Path):
    packages = registry.family_packages([str(root)], prefix="")
    assert packages == {10: "f10_box_tip"}
    tasks = {t.id: t for t in registry.collect(packages)}
    assert len(tasks) == 52 and tasks["10-box-tip"].implemented
    return tasks["10-box-tip"]


def test_the_example_family_registers_and_its_reference_scores_its_golden_score(example):
    task = _task(example)
    assert task.workflow == "mechanical_design"
    assert "| `stands` | 0.50 |" in task.instruction
    ref = declaration(task).get("reference")
    directory = materialise(task, "reference")
    assert artifact_sha256(directory) == ref.sha256
    ctx = VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True)
    report, internal = run_verify(task, directory, ctx)
    assert not internal and report.valid and report.score == pytest.approx(ref.quick_score, abs=1e-9)
    # closed form: a = g w / h = 9.81 * 0.25 / 0.3
    assert report.checkpoint("stands").measured["a_tip"] == pytest.approx(9.81 * 0.25 / 0.3)


def test_the_example_verifier_fails_a_tall_box_for_its_named_reason(example, tmp_path):
    task = _task(example)
    bad = tmp_path / "tall"
    bad.mkdir()
    xml = (example / "f10_box_tip/solutions/reference/box.xml").read_text()
    (bad / "box.xml").write_text(xml.replace('size="0.25 0.25 0.3"', 'size="0.1 0.1 0.4"'))
    report, _ = run_verify(task, bad, VerifyContext(secret=Secret(PUBLIC_KEY, public=True)))
    # a = 9.81 * 0.1 / 0.4 = 2.45 m/s^2 < 3 m/s^2: it tips under any hidden acceleration
    stands = report.checkpoint("stands")
    assert stands.score == 0.0 and stands.message == "tips at 2.45 m/s^2"
    assert report.checkpoint("height").score == 1.0 and report.score == pytest.approx(0.5)
    missing = tmp_path / "empty"
    missing.mkdir()
    report, _ = run_verify(task, missing, VerifyContext(secret=Secret(PUBLIC_KEY, public=True)))
    assert report.score == 0.0 and not report.valid and report.errors[0].path == "box.xml"


# Worked example 2: family 11, two tasks over one metered environment.
BLOCK11 = re.compile(r"`(f11_slider/[^`]+)`.*?\n```[a-z]*\n(.*?)```", re.DOTALL)
PUBLIC = Secret(PUBLIC_KEY, public=True)


@pytest.fixture
def example11(tmp_path, monkeypatch):
    """Family 11 written to ``tmp_path``, registered, its ledgers recorded and pinned as the page says."""
    text = DOC.read_text()
    section = text[text.index("## Worked example 2") :]
    files = BLOCK11.findall(section)
    assert [f for f, _ in files] == [
        f"f11_slider/{rel}"
        for rel in (
            "__init__.py",
            "constants.py",
            "env.py",
            "session.py",
            "task.py",
            "scoring.py",
            "verifier.py",
            *(
                f"{t}/{f}"
                for t in ("reach", "hold")
                for f in ("__init__.py", "task.py", "instruction.md", "scoring.py", "verifier.py")
            ),
            "solutions/__init__.py",
            "solutions/record.py",
            "solutions/reach.py",
            "solutions/hold.py",
        )
    ]
    _write_family(section, files, tmp_path, monkeypatch)
    packages = registry.family_packages([str(tmp_path)], prefix="")
    assert packages == {11: "f11_slider"}
    tasks = {t.id: t for t in registry.collect(packages)}
    assert len(tasks) == 53 and tasks["11-reach"].implemented and tasks["11-hold"].implemented
    # python -m f11_slider.solutions.record, then pin what python -m rle_tasks.core.solutions prints
    from f11_slider.solutions import record

    for task_id, name in (("11-reach", "reach"), ("11-hold", "hold")):
        record.record(task_id, tmp_path / "f11_slider" / "solutions" / "reference" / name)
        module = tmp_path / "f11_slider" / "solutions" / f"{name}.py"
        sset = declaration(tasks[task_id])
        for sol in sset.solutions:
            build(sset, sol.name, tmp_path / "pins" / task_id / sol.name)
            got = artifact_sha256(tmp_path / "pins" / task_id / sol.name)
            module.write_text(module.read_text().replace('"<pin>"', f'"{got}"', 1))
        del sys.modules[f"f11_slider.solutions.{name}"]
    yield tasks
    for name in [m for m in sys.modules if m.startswith("f11_slider")]:
        del sys.modules[name]


def test_the_metered_example_family_serves_its_session_and_scores_its_references(example11):
    reach, hold = example11["11-reach"], example11["11-hold"]
    assert reach.budget.steps == 200 and "| `reach` | 1.00 |" in reach.instruction
    assert "| `near` | 0.50 |" in hold.instruction and "| `still` | 0.50 |" in hold.instruction
    # the development environment is the metered one of the attempt's secret; a 5 N push of one action
    # (10 semi-implicit Euler steps of dt = 0.01 s on 1 kg) moves the block a dt^2 n (n + 1) / 2
    import mujoco

    env = reach.make_dev_env(Path("."))
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    data.ctrl[0] = 5.0
    mujoco.mj_step(model, data, nstep=env.n_substeps)
    assert data.qpos[0] == pytest.approx(5.0 * 0.01**2 * 10 * 11 / 2, rel=1e-9)
    for task in (reach, hold):
        ref = declaration(task).get("reference")
        report, internal = run_verify(
            task, materialise(task, "reference"), VerifyContext(secret=PUBLIC, quick=True)
        )
        assert not internal and report.valid and report.score == pytest.approx(ref.quick_score, abs=1e-6)
        unsealed, _ = run_verify(task, materialise(task, "baseline/unsealed"), VerifyContext(secret=PUBLIC))
        assert unsealed.score == 0.0 and not unsealed.valid and unsealed.errors[0].code == "ledger.unsealed"
    # reach's score is its Linear curve of the miss: 1 - miss / 0.05 m
    report, _ = run_verify(reach, materialise(reach, "reference"), VerifyContext(secret=PUBLIC))
    miss = report.checkpoint("reach").measured["miss"]
    assert miss < 1e-3 and report.score == pytest.approx(1 - miss / 0.05)
    # a ledger of 11-reach is not one of 11-hold: the gate refuses it by name
    wrong, _ = run_verify(hold, materialise(reach, "reference"), VerifyContext(secret=PUBLIC))
    assert wrong.score == 0.0 and wrong.errors[0].code.startswith("ledger.")
