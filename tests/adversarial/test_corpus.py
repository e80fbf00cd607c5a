"""The adversarial artifact corpus (issue: verifiers that never crash, never leak, never lose data).

Every case of ``corpus.py`` is verified with a private secret; the report must name the expected code,
the score must stay within its bound, and neither the report nor the artifact may contain the secret
or a hidden seed. Cases whose verification runs the full family-08 physics batteries are marked
``physics``: by default a fixed sample of them runs (the reduced form), all with RLE_FULL_BATTERY=1;
so do the generated additions (``generated/``).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from rle_tasks.audit import AUDIT_SECRET, find_leaks, hidden_needles, load_corpus, run_case
from rle_tasks.cli import main

CASES = load_corpus()
FULL = os.environ.get("RLE_FULL_BATTERY") == "1"
# Family-08 submitted-code cases each run the whole static and dynamic battery (~10-30 s); the reduced
# form keeps one per fault class that the sandbox maps differently.
REDUCED_F08_CODE = {"code/08_raise_midway", "code/08_hang", "code/08_return_nan", "code/08_import_crash"}
# Family-08 design cases each run the quick verification (~20-30 s) to reach the same validity cap; the
# reduced form keeps the contract case and one build-ability case (each finding has a fast unit test
# in tests/f08_mobile_base/test_f08_integrity.py).
REDUCED_F08_PHYSICS = {"physics/f08_gravcomp", "physics/f08_battery_in_mid_air"}
# Family-07 code cases each play a pile (the smoke test); the reduced form keeps a hang, a bad action, a
# leak attempt through /proc and an attempt to import the verifier.
# Generated additions (rle_tasks/audit/generated.py): every one is checked at load time in
# tests/f08_mobile_base/test_f08_generated.py and tests/f09_gello/test_generated.py; the reduced form verifies one
# family-08 case (~25 s each) and the family-09 additions under link3.
REDUCED_GENERATED = {
    "generated/f08_body_under_chassis",
    "generated/f09_geom_on_link3",
    "generated/f09_hinge_joint_under_link3",
    "generated/f09_free_joint_under_link3",
}
REDUCED_F07_CODE = {
    "code/07_hang",
    "code/07_return_nan",
    "code/07_read_parent_environ",
    "code/07_import_verifier",
}


def _slow(case) -> bool:
    return case.name.startswith(("code/08_", "physics/f08_", "code/07_", "physics/07_", "generated/f08_"))


def _params():
    """All cases with RLE_FULL_BATTERY=1; otherwise family-08 code and design cases and family-07 code
    cases only from the reduced samples."""
    for c in CASES:
        if c.name.startswith("code/08_") and not FULL and c.name not in REDUCED_F08_CODE:
            continue
        if c.name.startswith("physics/f08_") and not FULL and c.name not in REDUCED_F08_PHYSICS:
            continue
        if c.name.startswith("code/07_") and not FULL and c.name not in REDUCED_F07_CODE:
            continue
        if c.name.startswith("generated/") and not FULL and c.name not in REDUCED_GENERATED:
            continue
        yield pytest.param(c, id=c.name, marks=[pytest.mark.physics] if _slow(c) else [])


def test_corpus_has_at_least_60_cases_with_unique_names():
    names = [c.name for c in CASES]
    assert len(names) >= 60
    assert len(set(names)) == len(names)


@pytest.mark.parametrize("case", list(_params()))
def test_case_gets_its_code_and_bound_and_leaks_nothing(case, tmp_path):
    result = run_case(case, tmp_path)
    assert result.ok, f"{case.name}: {result.why}; observed {result.observed}, score {result.score:.3f}"
    assert result.report.is_file()
    needles = hidden_needles(AUDIT_SECRET, [case.task_id])
    leaks = find_leaks([tmp_path / case.name.replace("/", "__")], needles)
    assert not leaks, f"hidden data in {leaks}"


def test_audit_command_prints_the_table(capsys):
    assert main(["audit-verifiers", "--filter", "ledger/"]) == 0
    out = capsys.readouterr().out
    assert "expected code" in out and "ledger/forged_key" in out
    n = sum(c.name.startswith("ledger/") for c in CASES)
    assert n >= 13 and f"{n} cases, {n} matching" in out


def test_leak_detector_finds_a_planted_seed(tmp_path):
    from rle_tasks.core.runtime.secrets import derive_seed

    (tmp_path / "report.json").write_text(f'{{"note": "{derive_seed(AUDIT_SECRET, "09-gello", 5)}"}}')
    assert find_leaks([tmp_path], hidden_needles(AUDIT_SECRET, ["09-gello"])) == [
        str(tmp_path / "report.json")
    ]


def test_no_planted_file_outside_the_sandbox():
    # The write_outside cases try to plant a reward file in /tmp; the sandbox must have stopped them.
    planted = Path("/tmp/rle_planted_reward.json")
    assert not planted.exists(), "a submitted module wrote outside its working directory"
