"""Pinned dependencies: one lock file of exact versions (``make lock``, uv), used by ``make``, CI and both
Harbor images, so the agent's self-checks, the verifier and the test suite run the same versions."""

from __future__ import annotations

import re
import tomllib
from importlib import metadata

from packaging.requirements import Requirement
from packaging.utils import canonicalize_name
from packaging.version import Version

from rle_design.paths import REPO_ROOT

PIN = re.compile(r"^([A-Za-z0-9][A-Za-z0-9._-]*)==([^\s;]+)$")


def _lock(name: str) -> dict[str, Version]:
    pins = {}
    for line in (REPO_ROOT / name).read_text().splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        match = PIN.match(line.strip())
        assert match, f"{name}: '{line}' is not an exact pin"
        pins[canonicalize_name(match[1])] = Version(match[2])
    return pins


def test_lock_pins_every_declared_dependency_exactly():
    pins = _lock("requirements.lock")
    project = tomllib.loads((REPO_ROOT / "pyproject.toml").read_text())["project"]
    declared = list(project["dependencies"])
    for extra in ("dev", "viz", "learn", "opt"):
        declared += project["optional-dependencies"][extra]
    for text in declared:
        req = Requirement(text)
        name = canonicalize_name(req.name)
        assert name in pins, f"{req.name} is declared in pyproject.toml but not locked"
        assert req.specifier.contains(pins[name], prereleases=True), (
            f"{req.name}=={pins[name]} violates {req}"
        )
    assert str(pins["torch"]) == "2.13.0+cpu"  # the CPU build


def test_this_environment_is_installed_from_the_lock():
    """``make`` installs the lock with ``--no-deps``: every locked package is present at its version."""
    wrong = {}
    for name, version in _lock("requirements.lock").items():
        try:
            installed = Version(metadata.version(name))
        except metadata.PackageNotFoundError:
            installed = None
        if installed != version:
            wrong[name] = (str(version), str(installed))
    assert not wrong, f"installed versions differ from requirements.lock (locked, installed): {wrong}"


def test_make_ci_and_images_use_the_lock(exported):
    makefile = (REPO_ROOT / "Makefile").read_text()
    assert "$(PY) -m pip install --quiet --no-deps -r $(LOCK)" in makefile
    stamp = next(line for line in makefile.splitlines() if line.startswith("$(STAMP):"))
    assert {"pyproject.toml", "$(LOCK)", "Makefile"} <= set(
        stamp.split(":", 1)[1].split()
    )  # rebuilt on change
    assert "uv pip compile" in makefile and "\nlock:" in makefile
    assert "'.[" not in makefile  # nothing resolves the open ranges of pyproject.toml
    assert "make test" in (REPO_ROOT / ".ci" / "run").read_text()
    lock = (REPO_ROOT / "requirements.lock").read_bytes()
    for task_dir in exported.values():
        for image in ("environment", "tests"):
            assert (task_dir / image / "requirements.lock").read_bytes() == lock
            dockerfile = (task_dir / image / "Dockerfile").read_text()
            # every line of the lock, torch's from PyTorch's index and the rest from the default one
            assert "grep -E '^torch==' /opt/rle-bench/requirements.lock > /tmp/torch.txt" in dockerfile
            assert "grep -vE '^torch==' /opt/rle-bench/requirements.lock > /tmp/rest.txt" in dockerfile
            assert "pip install --no-deps -r /tmp/torch.txt --extra-index-url" in dockerfile
            assert "pip install --no-deps -r /tmp/rest.txt \\\n" in dockerfile
            assert "pip install --no-deps robosuite==1.5.2" in dockerfile


def test_harbor_side_venv_is_locked():
    pins = _lock("requirements-harbor.lock")
    assert pins["harbor"] == Version("0.25.0")
