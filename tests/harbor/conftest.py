"""One export of every implemented task, shared by the Harbor tests of this folder."""

from __future__ import annotations

import pytest


def exported_specs():
    """The tasks of the shared export: every implemented task the exporter takes, except those whose
    images hold a built dataset (family 05: tested with a small stand-in dataset of their own), so that
    these tests do not depend on what this machine has built."""
    from rle_tasks.core.export.harbor.export import not_exportable
    from rle_tasks.core.registry import all_tasks

    return [t for t in all_tasks() if t.implemented and not not_exportable(t) and not t.harbor_data]


@pytest.fixture(scope="session", name="exported_specs")
def _exported_specs():
    return exported_specs()


@pytest.fixture(scope="session")
def exported(tmp_path_factory):
    """``{task id: task directory}`` of ``export_harbor`` over ``exported_specs``."""
    from rle_tasks.core.export.harbor.export import export_harbor

    out = tmp_path_factory.mktemp("harbor-export")
    return {p.name: p for p in export_harbor(out, exported_specs())}
