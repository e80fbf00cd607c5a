"""Record the shipped ledgers under the public key: ``python -m rle_tasks.f03_physical_reasoning.solutions.hidden_com``."""

from pathlib import Path

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret

from . import SHIPPED, record

HERE = Path(__file__).resolve().parent

for name in SHIPPED:
    # the reference reads the top view after its reset only: render no other (same scene, same fingerprint)
    record(name, Secret(PUBLIC_KEY, public=True), HERE / "ledgers" / name, camera_every=100_000)
    print(f"03-hidden-com {name}: recorded")
