"""OpenBLAS runs one kernel family on every x86-64 machine with AVX2 and FMA, so replays agree."""

from __future__ import annotations

import os
import subprocess
import sys

from rle_design import _blas_core


def test_kernel_family_follows_the_cpu_flags(tmp_path):
    avx512 = tmp_path / "avx512"
    avx512.write_text("processor\t: 0\nflags\t\t: fpu sse2 avx avx2 fma avx512f avx512dq\n")
    old = tmp_path / "old"
    old.write_text("processor\t: 0\nflags\t\t: fpu sse2 sse4_2 avx\n")
    assert _blas_core(str(avx512)) == "Haswell"
    assert _blas_core(str(old)) is None  # no AVX2: OpenBLAS keeps its own choice
    assert _blas_core(str(tmp_path / "absent")) is None


def test_importing_the_toolkit_first_pins_the_kernels():
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    code = "import rle_tasks, numpy, os; print(os.environ.get('OPENBLAS_CORETYPE'))"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == str(_blas_core())
    late = subprocess.run(
        [sys.executable, "-c", "import numpy, rle_design"], env=env, capture_output=True, text=True
    )
    if _blas_core() is not None:
        assert "numpy was imported before rle_design" in late.stderr
