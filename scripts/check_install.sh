#!/usr/bin/env bash
# Non-editable install check (not part of `make test`): install this checkout with `pip install .` into
# a fresh virtual environment, then, from outside the checkout, materialise the 09-gello, 03-cantilever
# and 01-turn-on-stove-l3 references, verify them with `rle verify` (quick mode, public development key)
# and compare the scores with the golden table; run a slice of `rle audit-verifiers` (its corpus ships
# with the package).
#
# Usage: scripts/check_install.sh [VENV] (default /tmp/venv-wheel; reused if it exists)
set -euo pipefail

SRC="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="${1:-/tmp/venv-wheel}"
PYTHON="${PYTHON:-python3.11}"
WORK="$(mktemp -d /tmp/rle-install-check.XXXXXX)"
export MUJOCO_GL="${MUJOCO_GL:-egl}" PYOPENGL_PLATFORM="${PYOPENGL_PLATFORM:-egl}"
export RLE_CACHE_DIR="$WORK/cache"
unset RLE_SECRET PYTHONPATH

# Build from a copy of the checkout's files (tracked and untracked, not ignored): pip's in-tree build
# would otherwise leave build/ and *.egg-info in the checkout.
mkdir -p "$WORK/src"
git -C "$SRC" ls-files -z --cached --others --exclude-standard \
    | (cd "$SRC" && xargs -0 sh -c 'for f; do [ -f "$f" ] && printf "%s\0" "$f"; done' sh) \
    | tar -C "$SRC" --null -T - -cf - | tar -C "$WORK/src" -xf -

[ -x "$VENV/bin/python" ] || "$PYTHON" -m venv "$VENV"
"$VENV/bin/pip" install --quiet --upgrade pip
"$VENV/bin/pip" install --quiet "$WORK/src"
"$VENV/bin/pip" install --quiet --force-reinstall --no-deps "$WORK/src"  # these files, not a cached build
# robosuite is an asset source only (arm MJCF and meshes), installed without its dependencies.
"$VENV/bin/pip" install --quiet --no-deps robosuite==1.5.2

cd "$WORK"  # outside the checkout: nothing may be read from it
"$VENV/bin/python" - "$SRC" <<'PY'
import sys
from pathlib import Path

import rle_design
import rle_tasks
from rle_design.paths import CATALOG_DIR

src = Path(sys.argv[1]).resolve()
for mod in (rle_design, rle_tasks):
    where = Path(mod.__file__).resolve()
    if where.is_relative_to(src):
        sys.exit(f"{mod.__name__} is imported from the checkout ({where}), not from the installed package")
print(f"installed packages: {Path(rle_tasks.__file__).parent.parent}")
print(f"catalogs: {CATALOG_DIR} ({len(list(CATALOG_DIR.glob('*.yaml')))} yaml files)")
PY
# One solution per kind of shipped file: 09's STL/XML, 03's ledger (.jsonl), 01's gzipped ledger (.gz).
for TASK in 09-gello 03-cantilever 01-turn-on-stove-l3; do
    REF="$("$VENV/bin/python" -c "from rle_tasks.core.solutions import materialise; print(materialise('$TASK', 'reference'))")"
    echo "materialised $TASK reference: $REF"
    t0=$(date +%s)
    "$VENV/bin/rle" verify "$TASK" "$REF" --quick --json "$WORK/$TASK.json"
    echo "rle verify $TASK --quick: $(( $(date +%s) - t0 )) s"
    "$VENV/bin/python" - "$WORK/$TASK.json" "$TASK" <<'PY'
import json
import sys

from rle_tasks.core.registry import get_task
from rle_tasks.core.solutions import declaration

report = json.load(open(sys.argv[1]))
sol = declaration(get_task(sys.argv[2])).get("reference")
print(f"score {report['score']!r} (golden {sol.quick_score!r}), secret {report['secret']}, "
      f"artifact {report['artifact_sha256'][:16]} (pinned {sol.sha256[:16]})")
if abs(report["score"] - sol.quick_score) > 1e-9 or report["artifact_sha256"] != sol.sha256:
    sys.exit("the installed package does not reproduce the golden score")
PY
done

"$VENV/bin/rle" audit-verifiers --filter ledger/
"$VENV/bin/rle" audit-verifiers --filter xml/09-include_dotdot
echo "install check passed ($WORK)"
