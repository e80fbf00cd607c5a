"""Verification inside the Harbor verifier container: ``python -m rle_tasks.core.export.harbor.reward``.

``tests/test.sh`` of an exported task runs this module as root. It turns one ``rle verify`` run into
Harbor's reward file so that nothing the verified code does can influence the reward:

1. The secret must be private (``RLE_SECRET`` set and non-empty); ``RLE_ALLOW_PUBLIC_KEY=1`` lets an
   operator smoke-test with the public development key, and the reward then says so
   (``secret_private`` 0).
2. Before any submitted code runs, the log directories are closed: ``/logs`` and ``/logs/verifier``
   become root-owned, mode 755, so the sandboxed child (uid ``nobody``) can create nothing in them;
   stale ``reward.*`` entries (files, symlinks, directories) are removed.
3. The artifact is copied into a private root-only directory and verified there; the report is
   written there too.
4. A verifier fault (non-zero exit of ``rle verify``, no report, a report without a private secret)
   ends the run with a non-zero status and no reward file: Harbor shows an error, never a score.
5. The reward is written to a fresh file (``O_EXCL | O_NOFOLLOW``, relative to a descriptor of the
   closed directory) and renamed over ``reward.json``; a failed write fails the run.

``reward.json`` holds flat numbers: ``reward`` (the task score), ``secret_private`` (1 or 0) and one
key per checkpoint (``checkpoint_reward`` for a checkpoint named ``reward``).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

from rle_tasks.core.verify import VerifierSetupError

SECRET_ENV = "RLE_SECRET"
ALLOW_PUBLIC_ENV = "RLE_ALLOW_PUBLIC_KEY"
QUICK_ENV = "RLE_VERIFY_QUICK"
"""``1``: the operator asks for the task's quick evaluation (``rle verify --quick``); the reward file
says ``partial`` 1 and ``rle index`` takes it only with ``--allow-partial``."""
REWARD_FILES = ("reward.json", "reward.txt")


def check_secret(environ: dict[str, str]) -> bool:
    """True when the secret is private; raises when it is missing and the public key is not allowed."""
    if environ.get(SECRET_ENV):
        return True
    if environ.get(ALLOW_PUBLIC_ENV) == "1":
        return False
    raise VerifierSetupError(
        f"{SECRET_ENV} is not set: an exported RLE-Bench task verifies only with a private secret. Set "
        f"{SECRET_ENV} in the environment of the host running harbor (e.g. `export {SECRET_ENV}=$(openssl "
        f"rand -hex 32)`), or set {SECRET_ENV}= and {ALLOW_PUBLIC_ENV}=1 for a smoke test with the public "
        "development key"
    )


def _remove(dir_fd: int, name: str) -> None:
    """Remove entry ``name`` of the directory ``dir_fd`` whatever it is (a symlink is not followed)."""
    try:
        st = os.lstat(name, dir_fd=dir_fd)
    except FileNotFoundError:
        return
    if stat.S_ISDIR(st.st_mode):
        fd = os.open(name, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=dir_fd)
        try:
            for entry in os.listdir(fd):
                _remove(fd, entry)
        finally:
            os.close(fd)
        os.rmdir(name, dir_fd=dir_fd)
    else:
        os.unlink(name, dir_fd=dir_fd)


def close_directory(path: Path) -> int:
    """Make ``path`` a root-owned directory of mode 755 and return a descriptor of it.

    Raises:
        VerifierSetupError: Not root, ``path`` is a symlink, or the mode cannot be set.
    """
    path.mkdir(parents=True, exist_ok=True)
    fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)
    try:
        os.fchown(fd, 0, 0)
        os.fchmod(fd, 0o755)
        st = os.fstat(fd)
    except OSError as exc:
        os.close(fd)
        raise VerifierSetupError(f"cannot close {path} to the sandboxed code: {exc}") from None
    if st.st_uid != 0 or st.st_mode & 0o022:
        os.close(fd)
        raise VerifierSetupError(f"{path} is still writable by other users (mode {oct(st.st_mode)})")
    return fd


def _create(dir_fd: int, name: str) -> int:
    """A fresh file ``name`` in the directory ``dir_fd`` (an existing entry is removed first)."""
    _remove(dir_fd, name)
    return os.open(name, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644, dir_fd=dir_fd)


def write_reward(dir_fd: int, reward: dict[str, float]) -> None:
    """Write ``reward.json`` atomically to a fresh file in the directory ``dir_fd``; stale
    ``reward.*`` entries are removed first. Raises OSError when any step fails (nothing is left)."""
    for name in REWARD_FILES:
        _remove(dir_fd, name)
    tmp = f".reward-{os.getpid()}.tmp"
    _remove(dir_fd, tmp)
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644, dir_fd=dir_fd)
    try:
        data = (json.dumps(reward) + "\n").encode()
        if os.write(fd, data) != len(data):
            raise OSError("short write of the reward file")
        os.fsync(fd)
    except BaseException:
        os.close(fd)
        _remove(dir_fd, tmp)
        raise
    os.close(fd)
    os.rename(tmp, "reward.json", src_dir_fd=dir_fd, dst_dir_fd=dir_fd)
    _remove(dir_fd, "reward.txt")


def reward_from_report(report: dict, secret_private: bool, oracle: bool = False) -> dict[str, float]:
    """Flat numbers of Harbor's reward file from a verifier report dict.

    A report of a privileged session (``ledger.privileged``: an operator's oracle trial) counts only when
    the verifier was told it verifies the oracle (``oracle``: ``RLE_ORACLE_PRIVILEGED=1``); otherwise
    its reward and checkpoints are 0 and ``privileged`` says why."""
    privileged = any(e.get("code") == "ledger.privileged" for e in report.get("errors", []))
    void = privileged and not oracle
    reward = {
        "reward": 0.0 if void else float(report["score"]),
        "secret_private": 1.0 if secret_private else 0.0,
    }
    if privileged:
        reward["privileged"] = 1.0
    if report.get("partial"):
        reward["partial"] = 1.0
    for checkpoint in report.get("checkpoints", []):
        key = checkpoint["id"] if checkpoint["id"] not in reward else f"checkpoint_{checkpoint['id']}"
        reward[key] = 0.0 if void else float(checkpoint["score"])
    return reward


def sidecar_session(sidecar: Path) -> tuple[Path, str]:
    """(ledger, attempt) the development sidecar left (``harbor.sidecar.seal``), collected by Harbor.

    Raises:
        VerifierSetupError: the sidecar left no attempt (it did not run): no reward.
    """
    try:
        attempt = (sidecar / "attempt").read_text().strip()
    except OSError as exc:
        raise VerifierSetupError(f"the development sidecar left no attempt in {sidecar}: {exc}") from None
    return sidecar / "ledger.jsonl", attempt


def run(task_id: str, logs: Path, jobs: int, environ: dict[str, str], sidecar: Path | None = None) -> int:
    """Verify ``logs/artifacts`` for ``task_id`` and write ``logs/verifier/reward.json``.

    With ``sidecar`` (the development server's ledger directory, collected from the sidecar) the
    artifact's ``ledger.jsonl`` is that session's ledger, whatever the agent wrote, and the report
    is verified as the sidecar's attempt (``rle verify --attempt``).

    Returns:
        0 with a reward written; 1 (no reward file) on any verifier-side fault.
    """
    if os.geteuid() != 0:
        raise VerifierSetupError(
            "the verifier must run as root so that submitted code runs as an unprivileged user "
            "(leave [verifier] user unset in task.toml)"
        )
    private = check_secret(environ)
    os.close(close_directory(logs))  # /logs too: nobody may swap /logs/verifier for its own directory
    vfd = close_directory(logs / "verifier")
    for name in REWARD_FILES:
        _remove(vfd, name)
    work = Path(tempfile.mkdtemp(prefix="rle-verify-"))  # root-only (mode 700)
    try:
        artifacts = work / "artifacts"
        if (logs / "artifacts").is_dir():
            shutil.copytree(logs / "artifacts", artifacts, symlinks=True)
        else:
            artifacts.mkdir()
        report_path = work / "report.json"
        cmd = ["rle", "verify", task_id, str(artifacts), "--json", str(report_path), "--jobs", str(jobs)]
        if sidecar is not None:
            ledger, attempt = sidecar_session(sidecar)
            target = artifacts / "ledger.jsonl"  # the agent's own file never stands in for the session's
            if target.is_dir() and not target.is_symlink():
                shutil.rmtree(target)
            elif target.exists() or target.is_symlink():
                target.unlink()
            if ledger.is_file():
                shutil.copyfile(ledger, target)
            cmd += ["--attempt", attempt]
        if environ.get(QUICK_ENV) == "1":
            cmd.append("--quick")
        with open(_create(vfd, "verify.log"), "wb") as log:
            status = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, env=environ).returncode
        if report_path.is_file():  # a copy for the operator; the reward is computed from the private one
            with open(_create(vfd, "report.json"), "wb") as out:
                out.write(report_path.read_bytes())
        if status != 0:
            raise VerifierSetupError(f"`rle verify` failed with status {status} (see verify.log): no reward")
        if not report_path.is_file():
            raise VerifierSetupError("`rle verify` wrote no report: no reward")
        report = json.loads(report_path.read_text())
        if (report.get("secret") == "private") != private:
            raise VerifierSetupError(
                f"the report was made with the {report.get('secret')} key, expected "
                f"{'private' if private else 'public'}: no reward"
            )
        write_reward(vfd, reward_from_report(report, private, environ.get("RLE_ORACLE_PRIVILEGED") == "1"))
    finally:
        os.close(vfd)
        shutil.rmtree(work, ignore_errors=True)
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rle_tasks.core.export.harbor.reward")
    parser.add_argument("task")
    parser.add_argument("--logs", default="/logs")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--sidecar", default=None, help="ledger directory collected from the dev sidecar")
    args = parser.parse_args(argv)
    try:
        sidecar = Path(args.sidecar) if args.sidecar else None
        return run(args.task, Path(args.logs), args.jobs, dict(os.environ), sidecar)
    except (VerifierSetupError, OSError, ValueError, KeyError) as exc:
        print(f"rle-bench verifier error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
