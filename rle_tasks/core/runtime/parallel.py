"""Fan independent work items (variants, seeds, scenes) out to processes or a Ray cluster.

``run_parallel(fn, items, jobs=...)`` returns ``[fn(item) for item in items]`` in input order:

* ``jobs=1``: in this process, one item after the other (deterministic, the simplest to debug);
* ``executor="local"``: a ``concurrent.futures`` process pool with the ``spawn`` start method, so
  ``fn`` and the items must be picklable (a module-level function, not a lambda or closure);
* ``executor="ray"``: Ray tasks, imported lazily (``pip install 'rle-bench[dist]'``); a local Ray
  with ``num_cpus=jobs`` unless ``ray_address`` names a cluster. ``RAY_AUTH_MODE=disabled`` is set
  so that a local Ray does not write a token into ``$HOME``.

A verifier fans out typed units (a frozen dataclass per family: a seed, a pile, an arm's part, an
episode group) with ``run_units(fn, units, ctx)``, which takes ``jobs``, ``executor`` and
``ray_address`` from its context.

An exception raised by ``fn`` reaches the caller with its own type; a note added to it
(``exc.__notes__``, printed with the traceback) names the item that failed. The first failure
cancels the items that have not started.
"""

from __future__ import annotations

import multiprocessing
import os
import pickle
from collections.abc import Callable, Iterable
from concurrent.futures import FIRST_EXCEPTION, Future, ProcessPoolExecutor, wait
from typing import Any, Protocol, TypeVar

from rle_design.errors import RleError

T = TypeVar("T")
R = TypeVar("R")
Progress = Callable[[int, int], None]
EXECUTORS = ("local", "ray")


class Fanout(Protocol):
    """What ``run_units`` reads of a context (``VerifyContext`` has it)."""

    jobs: int
    executor: str
    ray_address: str | None


class RunnerError(RleError):
    """The runner was configured wrongly (executor, jobs, unpicklable function, Ray missing)."""

    code = "runner.config"


def _describe(item: Any, limit: int = 120) -> str:
    text = repr(item)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _annotate(exc: BaseException, index: int, item: Any) -> BaseException:
    exc.add_note(f"raised by run_parallel item {index}: {_describe(item)}")
    return exc


def _check_picklable(fn: Callable[..., Any]) -> None:
    try:
        pickle.dumps(fn)
    except Exception as exc:
        name = getattr(fn, "__qualname__", repr(fn))
        raise RunnerError(
            f"function '{name}' cannot be sent to worker processes ({type(exc).__name__}: {exc}); "
            "use a module-level function (not a lambda or closure), or jobs=1",
            code="runner.pickle",
        ) from None


def _serial(fn: Callable[[T], R], items: list[T], progress: Progress | None) -> list[R]:
    out: list[R] = []
    for i, item in enumerate(items):
        try:
            out.append(fn(item))
        except Exception as exc:
            raise _annotate(exc, i, item) from None
        if progress:
            progress(i + 1, len(items))
    return out


def _worker_init(workers: int) -> None:
    """In each worker of a pool of ``workers`` processes: cameras drawn in turn, not in parallel threads
    (``rle_design.control.cameras.PARALLEL``), unless the operator chose otherwise, where the workers
    alone can fill the CPUs."""
    if workers >= (os.cpu_count() or 1):
        os.environ.setdefault("RLE_RENDER_THREADS", "0")


def _local(fn: Callable[[T], R], items: list[T], jobs: int, progress: Progress | None) -> list[R]:
    _check_picklable(fn)
    ctx = multiprocessing.get_context("spawn")
    workers = min(jobs, len(items))
    with ProcessPoolExecutor(
        max_workers=workers, mp_context=ctx, initializer=_worker_init, initargs=(workers,)
    ) as pool:
        futures: list[Future] = [pool.submit(fn, item) for item in items]
        index = {f: i for i, f in enumerate(futures)}
        pending = set(futures)
        done_count = 0
        while pending:
            done, pending = wait(pending, return_when=FIRST_EXCEPTION)
            failed = sorted(index[f] for f in done if f.exception() is not None)
            if failed:
                pool.shutdown(wait=True, cancel_futures=True)
                i = failed[0]
                exc = futures[i].exception()
                raise _annotate(exc, i, items[i])
            done_count += len(done)
            if progress:
                progress(done_count, len(items))
        return [f.result() for f in futures]


def ray_runtime_env() -> dict[str, Any]:
    """Ray's ``runtime_env`` for the workers: the driver's BLAS kernel family (``OPENBLAS_CORETYPE``,
    set by ``import rle_design``). A Ray worker loads numpy before it unpickles a task, so the pin must
    be in its environment when it starts, or replays on the cluster round differently."""
    core = os.environ.get("OPENBLAS_CORETYPE")
    return {"env_vars": {"OPENBLAS_CORETYPE": core}} if core else {}


def _ray(
    fn: Callable[[T], R], items: list[T], jobs: int, address: str | None, progress: Progress | None
) -> list[R]:
    os.environ.setdefault("RAY_AUTH_MODE", "disabled")
    try:
        import ray
    except ImportError:
        raise RunnerError(
            "executor 'ray' needs Ray, which is not installed. Install it with: pip install 'rle-bench[dist]'",
            code="runner.ray_missing",
        ) from None
    started = False
    if not ray.is_initialized():
        if address:
            ray.init(address=address, log_to_driver=False, runtime_env=ray_runtime_env())
        else:
            ray.init(
                num_cpus=jobs, include_dashboard=False, log_to_driver=False, runtime_env=ray_runtime_env()
            )
        started = True
    try:
        remote = ray.remote(fn)
        refs = [remote.remote(item) for item in items]
        position = {ref: i for i, ref in enumerate(refs)}
        pending = list(refs)
        results: dict[int, Any] = {}
        while pending:
            ready, pending = ray.wait(pending, num_returns=1)
            for ref in ready:
                i = position[ref]
                try:
                    results[i] = ray.get(ref)
                except Exception as exc:
                    for other in pending:
                        ray.cancel(other)
                    cause = getattr(exc, "cause", None)
                    raise _annotate(cause if isinstance(cause, Exception) else exc, i, items[i]) from None
            if progress:
                progress(len(results), len(items))
        return [results[i] for i in range(len(items))]
    finally:
        if started:
            ray.shutdown()


def run_parallel(
    fn: Callable[[T], R],
    items: Iterable[T],
    *,
    jobs: int = 1,
    executor: str = "local",
    ray_address: str | None = None,
    progress: Progress | None = None,
) -> list[R]:
    """Apply ``fn`` to every item, possibly in parallel, and return the results in input order.

    Args:
        fn: Function of one item. For ``jobs > 1`` it must be picklable (module level).
        items: Work items (picklable for ``jobs > 1``).
        jobs: Worker processes (local) or CPUs of a local Ray. ``1`` runs in this process.
        executor: ``"local"`` or ``"ray"``.
        ray_address: Ray cluster address; None starts a local Ray with ``num_cpus=jobs``.
        progress: Called as ``progress(done, total)`` after items complete.

    Returns:
        ``[fn(item) for item in items]``.

    Raises:
        RunnerError: Unknown executor, ``jobs < 1``, unpicklable ``fn``, or Ray not installed.
        Exception: Whatever ``fn`` raised, with a note naming the item.
    """
    if executor not in EXECUTORS:
        raise RunnerError(f"executor '{executor}' is unknown. Available executors: {', '.join(EXECUTORS)}")
    if int(jobs) != jobs or jobs < 1:
        raise RunnerError(f"jobs must be a positive integer, got {jobs!r}")
    work = list(items)
    if not work:
        return []
    if executor == "ray" and (jobs > 1 or ray_address is not None):
        return _ray(fn, work, int(jobs), ray_address, progress)
    if jobs == 1 or len(work) == 1:
        return _serial(fn, work, progress)
    return _local(fn, work, int(jobs), progress)


def run_units(
    fn: Callable[[T], R],
    units: Iterable[T],
    ctx: Fanout,
    *,
    max_jobs: int | None = None,
    progress: Progress | None = None,
) -> list[R]:
    """``run_parallel`` of ``units`` with the context's ``jobs`` (at most ``max_jobs``), executor and
    Ray address."""
    jobs = ctx.jobs if max_jobs is None else max(1, min(ctx.jobs, max_jobs))
    return run_parallel(
        fn, units, jobs=jobs, executor=ctx.executor, ray_address=ctx.ray_address, progress=progress
    )
