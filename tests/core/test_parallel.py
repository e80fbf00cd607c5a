"""run_parallel: input order, in-process jobs=1, spawn pool, error propagation naming the item."""

import importlib.util
import os
import time

import pytest

from rle_tasks.core.runtime.parallel import RunnerError, run_parallel


def slow_square(x: int) -> tuple[int, int]:
    """Later items finish first, so completion order is the reverse of input order."""
    time.sleep(0.05 * (4 - x) if 0 <= x < 4 else 0)
    return x * x, os.getpid()


def fail_on_three(x: int) -> int:
    if x == 3:
        raise ValueError(f"bad item {x}")
    return x


def test_jobs_1_runs_in_process_in_order():
    seen = []
    out = run_parallel(lambda x: seen.append(x) or x + 1, range(5))  # closures are fine in-process
    assert out == [1, 2, 3, 4, 5] and seen == [0, 1, 2, 3, 4]


def test_local_pool_keeps_input_order_and_uses_other_processes():
    calls = []
    out = run_parallel(slow_square, range(4), jobs=2, progress=lambda d, n: calls.append((d, n)))
    assert [v for v, _ in out] == [0, 1, 4, 9]
    pids = {pid for _, pid in out}
    assert pids and os.getpid() not in pids
    assert calls[-1] == (4, 4) and all(n == 4 for _, n in calls)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)


@pytest.mark.parametrize("jobs", [1, 2])
def test_exception_propagates_with_the_item_named(jobs):
    with pytest.raises(ValueError, match="bad item 3") as exc:
        run_parallel(fail_on_three, [0, 1, 2, 3, 4], jobs=jobs)
    assert exc.value.__notes__ == ["raised by run_parallel item 3: 3"]


def test_unpicklable_function_is_refused_with_a_hint():
    with pytest.raises(RunnerError) as exc:
        run_parallel(lambda x: x, [1, 2], jobs=2)
    msg = str(exc.value)
    assert msg.startswith(
        "function 'test_unpicklable_function_is_refused_with_a_hint.<locals>.<lambda>' cannot be"
    )
    assert msg.endswith("use a module-level function (not a lambda or closure), or jobs=1")


def test_configuration_errors():
    with pytest.raises(RunnerError, match="^executor 'dask' is unknown. Available executors: local, ray$"):
        run_parallel(fail_on_three, [1], executor="dask")
    with pytest.raises(RunnerError, match="^jobs must be a positive integer, got 0$"):
        run_parallel(fail_on_three, [1], jobs=0)
    assert run_parallel(fail_on_three, [], jobs=4) == []


if importlib.util.find_spec("ray") is None:

    def test_ray_missing_gives_install_hint():
        with pytest.raises(RunnerError) as exc:
            run_parallel(fail_on_three, [1, 2], jobs=2, executor="ray")
        assert str(exc.value) == (
            "executor 'ray' needs Ray, which is not installed. Install it with: pip install 'rle-bench[dist]'"
        )
        assert exc.value.code == "runner.ray_missing"

else:

    def test_ray_keeps_order_and_names_failing_item():
        # Ray workers import functions by module: use a pure-Python standard-library function, not
        # this test module (which workers cannot import).
        import json

        assert run_parallel(json.loads, ["0", "1", "[4]", "9"], jobs=2, executor="ray") == [0, 1, [4], 9]
        with pytest.raises(ValueError, match="Expecting property name") as exc:
            run_parallel(json.loads, ["1", "4", "{"], jobs=2, executor="ray")
        assert exc.value.__notes__[-1] == "raised by run_parallel item 2: '{'"


def test_ray_workers_get_the_drivers_blas_kernel_family(monkeypatch):
    """A Ray worker imports numpy before it unpickles a task, so the pin travels in its environment."""
    import json
    import sys
    import types

    from rle_tasks.core.runtime.parallel import ray_runtime_env

    calls = []
    fake = types.SimpleNamespace(
        is_initialized=lambda: False,
        init=lambda **kw: calls.append(kw),
        shutdown=lambda: None,
        remote=lambda fn: types.SimpleNamespace(remote=lambda item: ("ref", item)),
        wait=lambda pending, num_returns: (pending[:1], pending[1:]),
        get=lambda ref: json.loads(ref[1]),
    )
    monkeypatch.setitem(sys.modules, "ray", fake)
    monkeypatch.setenv("OPENBLAS_CORETYPE", "Haswell")
    assert run_parallel(json.loads, ["1", "[2]"], jobs=2, executor="ray") == [1, [2]]
    assert calls[0]["runtime_env"] == {"env_vars": {"OPENBLAS_CORETYPE": "Haswell"}}
    monkeypatch.delenv("OPENBLAS_CORETYPE")
    assert ray_runtime_env() == {}
