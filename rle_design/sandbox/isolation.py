"""Parent-side preparation of the child: working directory, environment, unprivileged ids."""

from __future__ import annotations

import grp
import os
import pwd
import shutil
import tempfile
from collections.abc import Mapping
from pathlib import Path

#: Environment variables passed to the child; nothing else of the parent's environment crosses.
_PASSED = ("PATH", "LANG", "LC_ALL", "TZ", "MUJOCO_GL", "PYOPENGL_PLATFORM")
_THREADS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")


def child_env(workdir: Path) -> dict[str, str]:
    """Scrubbed environment: an allowlist of locale/display variables, HOME and TMPDIR in ``workdir``."""
    env = {k: os.environ[k] for k in _PASSED if k in os.environ}
    env.setdefault("PATH", "/usr/local/bin:/usr/bin:/bin")
    env.setdefault("LANG", "C.UTF-8")
    env["HOME"] = str(workdir)
    env["TMPDIR"] = str(workdir / "tmp")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    env["MPLCONFIGDIR"] = str(workdir / "tmp")
    for k in _THREADS:
        env[k] = "1"
    return env


def drop_ids() -> tuple[int, int] | None:
    """(uid, gid) of ``nobody``/``nogroup`` when running as root, else None (no privilege drop)."""
    if os.geteuid() != 0:
        return None
    try:
        uid = pwd.getpwnam("nobody").pw_uid
    except KeyError:
        uid = 65534
    for group in ("nogroup", "nobody"):
        try:
            return uid, grp.getgrnam(group).gr_gid
        except KeyError:
            continue
    return uid, 65534


def copy_tree(src: Path, dest: Path) -> None:
    """Copy regular files and directories of ``src`` into ``dest``; symlinks and special files are skipped."""
    for root, dirs, files in os.walk(src, followlinks=False):
        rel = Path(root).relative_to(src)
        dirs[:] = [d for d in dirs if not (Path(root) / d).is_symlink() and d != "__pycache__"]
        for d in dirs:
            (dest / rel / d).mkdir(exist_ok=True)
        for f in files:
            path = Path(root) / f
            if path.is_symlink() or not path.is_file():
                continue
            shutil.copyfile(path, dest / rel / f)


def give_to(workdir: Path, uid: int, gid: int) -> None:
    """Make ``workdir`` and everything in it owned by ``uid:gid``, private to that user."""
    os.chown(workdir, uid, gid)
    os.chmod(workdir, 0o700)
    for root, dirs, files in os.walk(workdir):
        for name in dirs + files:
            os.chown(os.path.join(root, name), uid, gid, follow_symlinks=False)


def make_workdir(module_dir: Path, files: Mapping[str, Path], ids: tuple[int, int] | None) -> Path:
    """A fresh working directory for a child: ``module_dir``'s contents, the extra ``files``
    ``{relative name: source}``, an empty ``tmp/``, owned by ``ids`` (uid, gid) where given.

    Raises:
        ValueError: an extra file's name escapes the directory.
    """
    workdir = Path(tempfile.mkdtemp(prefix="rle-sandbox-"))
    try:
        copy_tree(module_dir, workdir)
        for rel, src in files.items():
            dest = (workdir / rel).resolve()
            if not dest.is_relative_to(workdir.resolve()):
                raise ValueError(f"workdir file name {rel!r} escapes the working directory")
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(src, dest)
        (workdir / "tmp").mkdir(exist_ok=True)
        if ids is not None:
            give_to(workdir, *ids)
    except BaseException:
        shutil.rmtree(workdir, ignore_errors=True)
        raise
    return workdir
