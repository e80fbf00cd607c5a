"""Post-install check: offscreen OpenGL for renders. Prints the apt line when it is missing."""

import os
import subprocess
import sys

APT_HINT = "sudo apt-get update && sudo apt-get install -y libegl1 libgl1-mesa-dri libosmesa6 (or: bash scripts/apt-deps.sh)"

code = "import mujoco; mujoco.Renderer(mujoco.MjModel.from_xml_string('<mujoco/>'), 16, 16).close()"
env = dict(os.environ, MUJOCO_GL=os.environ.get("MUJOCO_GL", "egl"))
res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
if res.returncode != 0:
    print(f"warning: offscreen rendering with MUJOCO_GL={env['MUJOCO_GL']} failed; renders will be skipped.")
    print(f"         install the system libraries: {APT_HINT}")
else:
    print(f"offscreen rendering OK (MUJOCO_GL={env['MUJOCO_GL']})")
