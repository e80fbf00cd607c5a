"""One export of every implemented task, shared by the Harbor tests of this folder."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def exported(tmp_path_factory):
    """``{task id: task directory}`` of ``export_harbor`` over the registry's implemented tasks."""
    from rle_tasks.core.harbor import export_harbor

    out = tmp_path_factory.mktemp("harbor-export")
    return {p.name: p for p in export_harbor(out)}
