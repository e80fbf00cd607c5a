"""Import layering: the toolkit never imports the tasks, families never import each other, core and the
command line never name a family, and a family's public modules import only the toolkit."""

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FAMILY = re.compile(r"rle_tasks\.(f\d\d_[a-z0-9_]+)")


def _imports(path: Path, root: Path = ROOT) -> list[tuple[int, str]]:
    """(line, module) of every import in a file, relative imports resolved to absolute names."""
    tree = ast.parse(path.read_text(), filename=str(path))
    pkg = ".".join(path.relative_to(root).with_suffix("").parts[:-1])
    out = []
    for node in ast.walk(tree):
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


def test_core_and_shared_environments_never_name_a_family():
    files = _py("rle_tasks/core") + (_py("rle_tasks/envs") if (ROOT / "rle_tasks/envs").is_dir() else [])
    assert _violations(files, lambda p, m: FAMILY.match(m) is not None) == []


def test_command_line_never_names_a_family():
    top = [ROOT / "rle_tasks" / n for n in ("cli.py", "demo.py") if (ROOT / "rle_tasks" / n).exists()]
    assert _violations(top, lambda p, m: FAMILY.match(m) is not None) == []


def test_public_modules_import_only_the_toolkit():
    files = sorted((ROOT / "rle_tasks").glob("f*_*/public/**/*.py"))

    def bad(p: Path, mod: str) -> bool:
        return mod == "rle_tasks" or mod.startswith("rle_tasks.") and ".public" not in mod

    assert _violations(files, bad) == []
