"""Reads what no fresh agent may: the task package's scene generator, another process's environment and
the secret's usual places; the sandbox refuses each (the first refusal ends the agent)."""

import os
from pathlib import Path


def solve(client, instruction):
    client.reset()
    targets = [f"/proc/{os.getppid()}/environ", "/root/.cache/rle-bench", "/work"]
    for target in targets:
        path = Path(target)
        if path.is_dir():
            return sorted(p.name for p in path.iterdir())
        return path.read_bytes()[:100]
    return None
