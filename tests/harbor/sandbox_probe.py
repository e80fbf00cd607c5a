"""Run inside the exported verifier image (``test_harbor_images.py``): a sandboxed submission tries to
read, list and import the verifier package, and imports the public toolkit; prints what it saw."""

import json
import pathlib
import tempfile

import rle_tasks
from rle_design.sandbox import Sandbox, SandboxLimits

SUBMISSION = """
import os, sys
VERIFIER = "/opt/rle-bench/rle_tasks/f09_gello/verifier.py"


def probe():
    out = {"sys_path": [p for p in sys.path if p.startswith("/opt")]}
    tries = (("read", lambda: open(VERIFIER).read(64)), ("list", lambda: os.listdir("/opt/rle-bench/rle_tasks")))
    for key, action in tries:
        try:
            action()
            out[key] = "allowed"
        except OSError as exc:
            out[key] = type(exc).__name__
    try:
        import rle_tasks.f09_gello.verifier
        out["import"] = "imported"
    except ImportError:
        out["import"] = "ImportError"
    import rle_design.kinematics
    out["toolkit"] = "ok"
    return out
"""

work = pathlib.Path(tempfile.mkdtemp())
(work / "submission.py").write_text(SUBMISSION)
with Sandbox(work / "submission.py", limits=SandboxLimits(call_timeout_s=120)) as box:
    seen = box.call("probe")
seen["editable"] = str(pathlib.Path(rle_tasks.__file__)).startswith("/opt/rle-bench")
print(json.dumps(seen))
