"""MuJoCo's asset cache is widened in every process that imports the tasks: with the default 500 MiB, a
process that builds a kitchen (its meshes 115 MB), the G1 (147 MB) and the object catalogue (262 MB)
evicts meshes and processes them again at every compile (ten times slower kitchen tests)."""

import subprocess
import sys

from rle_design import MJ_ASSET_CACHE_BYTES


def test_importing_the_tasks_widens_mujocos_asset_cache():
    code = "import mujoco; d = mujoco.mj_getCacheCapacity(mujoco.mj_getCache()); import rle_tasks; "
    code += "print(d, mujoco.mj_getCacheCapacity(mujoco.mj_getCache()))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    default, widened = map(int, out.split())
    assert default == 500 * 1024 * 1024 < widened == MJ_ASSET_CACHE_BYTES
