"""docs/adding-a-family.md: its worked example, written out as it stands, is a working family."""

import re
import sys
from pathlib import Path

import pytest
import yaml

from rle_tasks.core import families as families_mod
from rle_tasks.core import registry
from rle_tasks.core.report import artifact_sha256
from rle_tasks.core.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.core.verify import run_verify

DOC = Path(__file__).resolve().parents[2] / "docs" / "adding-a-family.md"
BLOCK = re.compile(r"`(f10_box_tip/[^`]+)`.*?\n```[a-z]*\n(.*?)```", re.DOTALL)


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
    for rel, body in files:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(body)
    (tmp_path / "f10_box_tip" / "assets").mkdir()
    line = yaml.safe_load(re.search(r"```yaml\n(.*?)```", text, re.DOTALL).group(1))[0]
    info = families_mod.FamilyInfo(line["number"], line["slug"], line["workflow"], line["title"])
    known = families_mod.families()
    monkeypatch.setattr(families_mod, "families", lambda: (*known, info))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("RLE_CACHE_DIR", str(tmp_path / "cache"))
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
