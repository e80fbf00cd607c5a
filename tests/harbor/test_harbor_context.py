"""The agent image's build context holds the public toolkit and the task's public workspace only.

For every implemented task (registry order, no family named here), every file of ``environment/`` is
classified: the Dockerfile and dependency list, a byte-identical copy of a public toolkit file
(``rle_design``), or a byte-identical copy of what ``rle dev`` lays out. Any other file fails, and so
does any file whose content equals a shipped solution file (reference or baseline) that ``rle dev``
does not itself publish, or a verifier-side module of ``rle_tasks`` (verifier, generators, scoring).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from rle_design.paths import REPO_ROOT
from rle_tasks.core.runtime.devenv import layout_workspace
from rle_tasks.core.solutions import materialise

FORBIDDEN_PARTS = {"rle_tasks", "solutions", "reference", "baseline", "design_gen.py"}


def _files(root: Path) -> dict[str, str]:
    """``{relative path: sha256}`` of the regular files under ``root``."""
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
        if p.is_file() and "__pycache__" not in p.parts
    }


def _verifier_side_digests() -> dict[str, str]:
    """``{sha256: origin}`` of every non-empty ``rle_tasks`` file outside a family's ``public/``."""
    out = {}
    for p in (REPO_ROOT / "rle_tasks").rglob("*"):
        if not p.is_file() or "__pycache__" in p.parts or "public" in p.parts or p.suffix == ".md":
            continue
        data = p.read_bytes()
        if data.strip():
            out[hashlib.sha256(data).hexdigest()] = str(p.relative_to(REPO_ROOT))
    return out


def _solution_digests(spec) -> dict[str, str]:
    out = {}
    for name in spec.solutions:
        d = materialise(spec, name)
        out.update({h: f"solution {name}: {rel}" for rel, h in _files(d).items()})
    return out


def test_agent_context_holds_only_toolkit_and_public_workspace(exported, exported_specs, tmp_path):
    implemented = exported_specs
    assert sorted(exported) == sorted(t.id for t in implemented) and implemented
    toolkit = _files(REPO_ROOT / "rle_design")
    verifier_side = _verifier_side_digests()
    for spec in implemented:
        env = exported[spec.id] / "environment"
        public = _files(layout_workspace(spec, tmp_path / spec.id, serve=False).workspace)
        leaks = {**verifier_side, **_solution_digests(spec)}
        for h in set(public.values()) | set(toolkit.values()):
            leaks.pop(h, None)  # published by `rle dev` or the toolkit itself: public by definition
        problems = []
        for rel, digest in _files(env).items():
            if rel.startswith("dev/"):
                continue  # the development sidecar's context: never part of the agent's image (below)
            parts = set(Path(rel).parts)
            if parts & FORBIDDEN_PARTS:
                problems.append(f"{rel}: forbidden path component {sorted(parts & FORBIDDEN_PARTS)}")
            if digest in leaks:
                problems.append(f"{rel}: same bytes as {leaks[digest]}")
            if rel in ("Dockerfile", "requirements.lock", "docker-compose.yaml", ".dockerignore"):
                continue
            if rel.startswith("rle-bench/rle_design/"):
                ok = toolkit.get(rel.removeprefix("rle-bench/rle_design/")) == digest
            elif rel.startswith("workspace/"):
                ok = public.get(rel.removeprefix("workspace/")) == digest
            else:
                ok = rel == "rle-bench/LICENSE"
            if not ok:
                problems.append(f"{rel}: neither toolkit nor public workspace")
        assert not problems, f"{spec.id} agent context:\n" + "\n".join(problems)
        # everything `rle dev` lays out, its clients included (their server runs in the sidecar)
        shipped = {r.removeprefix("workspace/") for r in _files(env) if r.startswith("workspace/")}
        assert shipped == set(public)
        dockerfile = (env / "Dockerfile").read_text()
        assert "rle_tasks" not in dockerfile and "COPY workspace /workspace" in dockerfile
        if (env / "dev").exists():
            assert (env / ".dockerignore").read_text() == "dev/\n" and "COPY dev" not in dockerfile


def test_verifier_context_holds_the_whole_project(exported):
    for task_dir in exported.values():
        snap = task_dir / "tests" / "rle-bench"
        assert (snap / "rle_tasks" / "core" / "verify.py").is_file()
        assert (snap / "rle_design" / "sandbox" / "process.py").is_file()


def test_every_task_directory_has_an_operator_readme(exported, exported_specs):
    from rle_tasks.core.solutions import declaration

    for spec in exported_specs:
        text = (exported[spec.id] / "README.md").read_text()
        assert text.startswith(f"# rle-bench/{spec.id}: {spec.title}\n")
        if "reference" in spec.solutions:
            golden = f"{declaration(spec).get('reference').quick_score:.3f}"
            oracle = exported[spec.id] / "solution"
            if (oracle / "reference").is_dir() and "ledger.jsonl" in spec.contract.required:
                # a ledger task whose reference cannot play through the sidecar: the README says 0
                assert "scores **0**" in text and f"golden score (public key, quick mode) is {golden}" in text
            else:
                assert f"scores **{golden}**" in text
        assert 'export RLE_SECRET="$(openssl rand -hex 32)"' in text
        b = spec.budget
        assert f"| CPUs / memory / GPUs | {b.cpus} / {b.memory_mb} MiB / {b.gpus} |" in text
        assert f"| agent wall time | {b.wall_time_s / 3600:.1f} h |" in text
