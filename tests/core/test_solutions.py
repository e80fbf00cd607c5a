"""Shipped solutions: declarations, materialisation, pinned checksums, cache, stored once."""

from __future__ import annotations

import hashlib
import sys
from collections import defaultdict
from pathlib import Path

import pytest

import rle_tasks
from rle_design.errors import RleError
from rle_tasks.core.registry import all_tasks, get_task
from rle_tasks.core.report import artifact_sha256
from rle_tasks.core.solutions import CACHE_ENV, Solution, SolutionSet, declaration, edit_xml, materialise
from rle_tasks.core.task import TaskSpec

SHIPPING = [t for t in all_tasks() if t.solutions]
PKG = Path(rle_tasks.__file__).parent


@pytest.fixture
def cache(tmp_path, monkeypatch) -> Path:
    monkeypatch.setenv(CACHE_ENV, str(tmp_path / "cache"))
    return tmp_path / "cache"


def test_task_specs_name_exactly_their_declared_solutions():
    assert {t.id for t in SHIPPING} >= {"08-mobile-base", "09-gello"}
    for task in SHIPPING:
        assert task.solutions == declaration(task).names, task.id
        rest = (
            task.solutions[1:] if task.solutions[0] == "reference" else task.solutions
        )  # reference first, where shipped
        assert rest and all(n.startswith("baseline/") for n in rest), task.id


@pytest.mark.parametrize("task", SHIPPING, ids=[t.id for t in SHIPPING])
def test_every_solution_materialises_to_its_pinned_checksum_in_the_cache(task, cache):
    for name in task.solutions:
        d = materialise(task, name)
        assert d.is_relative_to(cache) and d.is_dir()
        assert artifact_sha256(d) == declaration(task).get(name).sha256
        assert materialise(task.id, name) == d  # cached


def test_the_package_tree_is_not_written(cache):
    before = {p: p.stat().st_mtime_ns for p in PKG.rglob("*") if "__pycache__" not in p.parts}
    for task in SHIPPING:
        for name in task.solutions:
            materialise(task, name)
    after = {p: p.stat().st_mtime_ns for p in PKG.rglob("*") if "__pycache__" not in p.parts}
    assert after == before


def test_an_altered_cache_copy_is_rebuilt(cache):
    d = materialise("08-mobile-base", "baseline/raising_controller")
    (d / "controller.py").write_text("def reset(*a):\n    pass\n")
    (d / "__pycache__").mkdir()
    assert materialise("08-mobile-base", "baseline/raising_controller") == d
    assert not (d / "__pycache__").exists()
    assert "deliberately failed" in (d / "controller.py").read_text()


def test_materialise_into_a_destination(tmp_path):
    d = materialise(get_task("09-gello"), "baseline/gravcomp_cheat", dest=tmp_path / "cheat")
    assert sorted(p.name for p in d.iterdir()) == ["panda", "ur5e", "xarm7"]
    assert sorted(p.name for p in (d / "ur5e").iterdir()) == ["lead.xml", "meshes", "trim.py"]
    assert 'gravcomp="1" name="link1"' in (d / "panda" / "lead.xml").read_text()
    with pytest.raises(RleError) as exc:
        materialise("09-gello", "reference", dest=d)
    assert exc.value.code == "solutions.dest"


def test_no_stl_or_solution_file_is_stored_twice():
    # Solution sources: everything under a family's solutions/ package and the trim templates.
    files = [p for p in PKG.rglob("*.stl")]
    files += [p for p in PKG.glob("*/solutions/**/*") if p.is_file() and "__pycache__" not in p.parts]
    files += list(PKG.glob("*/assets/trim_templates/*.py"))
    groups: dict[str, list[Path]] = defaultdict(list)
    for p in files:
        groups[hashlib.sha256(p.read_bytes()).hexdigest()].append(p)
    repeated = [sorted(g) for g in groups.values() if len(g) > 1]
    # One exception: a stock-leader part that is the same for every robot (each assets/<robot>/ is a
    # self-contained directory handed to the workspace as it is).
    for g in repeated:
        assert len({p.name for p in g}) == 1 and all(p.parent.parent.parent.name == "assets" for p in g), g
    assert all(p.is_relative_to(PKG / "f09_gello" / "assets") for p in PKG.rglob("*.stl"))


# ---------------------------------------------------------------- errors, with a small family package


def _family(tmp_path: Path, monkeypatch, declaration_text: str, name: str) -> TaskSpec:
    pkg = tmp_path / "pkgs" / name
    (pkg / "solutions" / "reference").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "solutions" / "reference" / "robot.xml").write_text("<mujoco/>\n")
    (pkg / "solutions" / "__init__.py").write_text(declaration_text)
    monkeypatch.syspath_prepend(str(tmp_path / "pkgs"))
    monkeypatch.setenv(CACHE_ENV, str(tmp_path / "cache"))
    return TaskSpec("99-fake", 9, "fake", solutions=("reference",), solutions_module=f"{name}.solutions")


def test_a_changed_source_fails_loudly(tmp_path, monkeypatch):
    text = (
        "from rle_tasks.core.solutions import Solution, SolutionSet\n"
        "SOLUTIONS = SolutionSet('fake_changed', (Solution('reference', sha256='0' * 64, quick_score=0.0,"
        " files=(('.', 'solutions/reference'),)),))\n"
    )
    task = _family(tmp_path, monkeypatch, text, "fake_changed")
    with pytest.raises(RleError) as exc:
        materialise(task, "reference")
    assert exc.value.code == "solutions.checksum"
    assert str(exc.value).startswith(
        "materialised solution 'reference' of task '99-fake' has checksum "
        f"{artifact_sha256(tmp_path / 'pkgs' / 'fake_changed' / 'solutions' / 'reference')}, but {'0' * 64} is pinned"
    )
    assert not list((tmp_path / "cache" / "solutions").iterdir())  # nothing half-built is left
    sys.modules.pop("fake_changed.solutions", None)


def test_unknown_solution_names_the_declared_ones():
    with pytest.raises(RleError) as exc:
        materialise("09-gello", "baseline/nope")
    assert exc.value.code == "solutions.unknown"
    assert str(exc.value) == (
        "solution 'baseline/nope' is not declared in rle_tasks.f09_gello. Declared: reference, "
        "baseline/uncompensated, baseline/gravcomp_cheat, baseline/over_mass, baseline/hanging_trim"
    )


def _noop(directory: Path) -> None:
    del directory


@pytest.mark.parametrize(
    ("solutions", "message"),
    [
        (
            (Solution("reference", "", 0.0), Solution("reference", "", 0.0)),
            "solution 'reference' is declared twice",
        ),
        (
            (Solution("baseline/a", "", 0.0, base="reference"),),
            "solution 'baseline/a' starts from 'reference', which is not declared before it. Declared: (none)",
        ),
        (
            (Solution("reference", "", 0.0, files=(("x", "../escape"),)),),
            "solution 'reference': path '../escape' must be relative, without '..'",
        ),
        ((Solution("reference", "", 0.0, transforms=(lambda d: None,)),), "must be a module-level function"),
    ],
)
def test_invalid_declarations_are_refused(solutions, message):
    with pytest.raises(RleError, match=message.replace("(", r"\(").replace(")", r"\)")) as exc:
        SolutionSet("rle_tasks.f08_mobile_base", solutions)
    assert exc.value.code == "solutions.invalid"
    SolutionSet("rle_tasks.f08_mobile_base", (Solution("reference", "", 0.0, transforms=(_noop,)),))


def test_edit_xml_round_trip_keeps_the_bytes(tmp_path):
    ref = materialise("08-mobile-base", "reference", dest=tmp_path / "ref")
    before = (ref / "robot.xml").read_bytes()
    edit_xml(ref / "robot.xml", lambda root: None)
    assert (ref / "robot.xml").read_bytes() == before and before.endswith(b"</mujoco>\n")
