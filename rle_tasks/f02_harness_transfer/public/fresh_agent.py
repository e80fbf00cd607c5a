"""The scripted fresh agent: what tests and the demo run in place of a fresh coding agent.

It sees what a fresh agent sees (its working directory holds ``agent_harness/``, ``instruction.md`` and
``client.py``), reads the harness manual ``agent_harness/MANUAL.md`` for its documented entry point, a
line ``Entry point: `package.module:function` `` (backticks optional), imports that function and calls
it once as ``function(client, instruction)`` with a connected metered client and the task's one-line
instruction. It adds no skill of its own: whatever the harness does is the score.

``run()`` returns a small report: ``status`` (``ran``, ``no_manual``, ``no_entry_point``,
``missing_function``) and a ``message``; an exception raised by the harness propagates (the verifier
records it as the harness's fault).
"""

import importlib
import re
import sys
from pathlib import Path

ENTRY = re.compile(r"entry\s+point\s*:\s*`?([A-Za-z_][\w.]*):([A-Za-z_]\w*)`?", re.IGNORECASE)
HERE = Path(__file__).resolve().parent


def _instruction() -> str:
    text = (HERE / "instruction.md").read_text()
    for line in text.splitlines():
        if line.startswith("Task: "):
            return line[len("Task: ") :].strip()
    return text.strip()


def run() -> dict:
    manual = HERE / "agent_harness" / "MANUAL.md"
    if not manual.is_file():
        return {"status": "no_manual", "message": "agent_harness/MANUAL.md does not exist"}
    found = ENTRY.search(manual.read_text(errors="replace"))
    if found is None:
        return {"status": "no_entry_point", "message": "MANUAL.md names no 'Entry point: `module:function`'"}
    module_name, function = found.groups()
    if str(HERE) not in sys.path:
        sys.path.insert(0, str(HERE))
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        return {
            "status": "missing_function",
            "message": f"entry point module {module_name} cannot be imported: {exc}",
        }
    fn = getattr(module, function, None)
    if not callable(fn):
        return {
            "status": "missing_function",
            "message": f"entry point {module_name}:{function} does not exist",
        }
    from client import connect

    with connect() as client:
        result = fn(client, _instruction())
    return {"status": "ran", "message": f"{module_name}:{function} returned {str(result)[:120]}"}
