"""Record the shipped ledgers under the public key: ``python -m rle_tasks.f03_physical_reasoning.solutions.pocket_cube``."""

from pathlib import Path

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret

from ...cube.scene import PUBLIC_SCRAMBLES, CubeInstance
from . import SECOND, SHIPPED, record

HERE = Path(__file__).resolve().parent
PUBLIC = Secret(PUBLIC_KEY, public=True)

for name in SHIPPED:
    kwargs = {"scramble": PUBLIC_SCRAMBLES[0]} if name == "reference" else {}
    record(name, PUBLIC, HERE / "ledgers" / name, **kwargs)
    print(f"03-pocket-cube {name}: recorded")
inst = CubeInstance.from_moves(PUBLIC_SCRAMBLES[1])
record("reference", PUBLIC, HERE / "ledgers" / SECOND, inst=inst, scramble=PUBLIC_SCRAMBLES[1])
print(f"03-pocket-cube reference on {PUBLIC_SCRAMBLES[1]!r}: recorded")
