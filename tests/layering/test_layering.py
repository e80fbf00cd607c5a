"""Import layering: the toolkit never imports the tasks, families never import each other, core and the
command line never name a family, and a family's public modules import only the toolkit."""

import ast
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FAMILY = re.compile(r"rle_tasks\.(f\d\d_[a-z0-9_]+)")


def _type_only(node: ast.AST) -> bool:
    """``if TYPE_CHECKING:`` (or ``typing.TYPE_CHECKING``): imports there never run."""
    test = getattr(node, "test", None)
    return isinstance(node, ast.If) and (
        (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING")
        or (isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")
    )


def _walk(node: ast.AST, runtime: bool):
    yield node
    for child in ast.iter_child_nodes(node):
        if not (runtime and _type_only(child)):
            yield from _walk(child, runtime)


def _imports(path: Path, root: Path = ROOT, runtime: bool = False) -> list[tuple[int, str]]:
    """(line, module) of every import in a file, relative imports resolved to absolute names;
    ``runtime`` leaves out the imports made only for type checkers."""
    tree = ast.parse(path.read_text(), filename=str(path))
    pkg = ".".join(path.relative_to(root).with_suffix("").parts[:-1])
    out = []
    for node in _walk(tree, runtime):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = pkg.split(".")[: len(pkg.split(".")) - node.level + 1]
                base = ".".join(parent + ([base] if base else []))
            out += [(node.lineno, f"{base}.{a.name}" if base else a.name) for a in node.names]
    return out


def _py(folder: str) -> list[Path]:
    return sorted((ROOT / folder).rglob("*.py"))


def _violations(files: list[Path], bad) -> list[str]:
    return [
        f"{p.relative_to(ROOT)}:{line} imports {mod}"
        for p in files
        for line, mod in _imports(p)
        if bad(p, mod)
    ]


def test_resolves_relative_imports(tmp_path):
    mod = tmp_path / "rle_tasks" / "f01_x" / "public" / "a.py"
    mod.parent.mkdir(parents=True)
    mod.write_text(
        "import os\nfrom . import b\nfrom ..scene import build\nfrom rle_design.mjcf import load_design\n"
    )
    assert _imports(mod, tmp_path) == [
        (1, "os"),
        (2, "rle_tasks.f01_x.public.b"),
        (3, "rle_tasks.f01_x.scene.build"),
        (4, "rle_design.mjcf.load_design"),
    ]


def test_toolkit_never_imports_tasks():
    assert _violations(_py("rle_design"), lambda p, m: m == "rle_tasks" or m.startswith("rle_tasks.")) == []


def test_families_never_import_each_other():
    def bad(p: Path, mod: str) -> bool:
        own = next(part for part in p.relative_to(ROOT / "rle_tasks").parts)
        m = FAMILY.match(mod)
        return m is not None and m.group(1) != own

    files = [p for p in _py("rle_tasks") if re.match(r"f\d\d_", p.relative_to(ROOT / "rle_tasks").parts[0])]
    assert files, "no family package found"
    assert _violations(files, bad) == []


def test_core_shared_environments_and_the_audit_runner_never_import_a_family():
    files = _py("rle_tasks/core") + _py("rle_tasks/audit")
    files += _py("rle_tasks/envs") if (ROOT / "rle_tasks/envs").is_dir() else []
    assert _violations(files, lambda p, m: FAMILY.match(m) is not None) == []


def test_command_line_never_names_a_family():
    top = [ROOT / "rle_tasks" / n for n in ("cli.py", "demo.py") if (ROOT / "rle_tasks" / n).exists()]
    assert _violations(top, lambda p, m: FAMILY.match(m) is not None) == []


def test_public_modules_import_only_the_toolkit():
    files = sorted((ROOT / "rle_tasks").glob("f*_*/public/**/*.py"))

    def bad(p: Path, mod: str) -> bool:
        return mod == "rle_tasks" or mod.startswith("rle_tasks.") and ".public" not in mod

    assert _violations(files, bad) == []


def _modules() -> dict[str, Path]:
    out = {}
    for folder in ("rle_design", "rle_tasks"):
        for p in _py(folder):
            parts = p.relative_to(ROOT).with_suffix("").parts
            out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = p
    return out


def import_cycles() -> set[frozenset[str]]:
    """Strongly connected components (more than one module) of the import graph of the toolkit and the
    tasks, function-level imports included (imports for type checkers only are not): ``from a import b``
    is an edge to ``a.b`` when that is a module, else to ``a``."""
    mods = _modules()
    edges = {m: set() for m in mods}
    for m, p in mods.items():
        for _, name in _imports(p, ROOT, runtime=True):
            target = name if name in mods else name.rsplit(".", 1)[0]
            if target in mods and target != m:
                edges[m].add(target)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: set[frozenset[str]] = set()

    def visit(v: str) -> None:  # Tarjan
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while not comp or comp[-1] != v:
                comp.append(stack.pop())
            if len(comp) > 1:
                found.add(frozenset(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return found


KNOWN_CYCLES: set[frozenset[str]] = set()
"""Import cycles tolerated: none (issue 40). Any cycle fails the test; this list may only shrink."""


def test_no_new_import_cycles_and_the_known_ones_only_shrink():
    cycles = import_cycles()
    new = cycles - KNOWN_CYCLES
    assert not new, "new import cycles:\n" + "\n".join(" <-> ".join(sorted(c)) for c in new)
    gone = KNOWN_CYCLES - cycles
    assert not gone, "removed cycles still listed in KNOWN_CYCLES:\n" + "\n".join(
        " ".join(sorted(c)) for c in gone
    )


def test_the_cycle_finder_finds_a_cycle_hidden_in_a_function_and_ignores_type_only_imports(
    tmp_path, monkeypatch
):
    pkg = tmp_path / "rle_tasks" / "f99_x"
    pkg.mkdir(parents=True)
    (tmp_path / "rle_design").mkdir()
    (tmp_path / "rle_tasks" / "__init__.py").write_text("")
    (pkg / "__init__.py").write_text("")
    (pkg / "task.py").write_text("def spec():\n    from .verifier import verify\n")
    (pkg / "verifier.py").write_text("from .task import spec\n")
    (pkg / "typed_a.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .typed_b import B\n"
    )
    (pkg / "typed_b.py").write_text("from .typed_a import A\n")  # a type-only import closes no cycle
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    assert import_cycles() == {frozenset({"rle_tasks.f99_x.task", "rle_tasks.f99_x.verifier"})}
