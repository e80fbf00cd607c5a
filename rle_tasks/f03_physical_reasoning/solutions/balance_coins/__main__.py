"""Record the shipped ledgers under the public key: ``python -m rle_tasks.f03_physical_reasoning.solutions.balance_coins``."""

from pathlib import Path

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret

from . import SHIPPED, record

HERE = Path(__file__).resolve().parent

for name in SHIPPED:
    record(name, Secret(PUBLIC_KEY, public=True), HERE / "ledgers" / name)
    print(f"03-balance-coins {name}: recorded")
