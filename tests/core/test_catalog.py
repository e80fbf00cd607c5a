import pytest

from rle_design.catalog import catalog_kinds, load_catalog, part_fragment_path
from rle_design.errors import CatalogError
from rle_design.scene import arm_model_path


@pytest.mark.parametrize("kind", catalog_kinds())
def test_catalog_loads_with_units_and_unique_ids(kind):
    cat = load_catalog(kind)
    assert len(cat) > 0
    assert len(set(cat.ids)) == len(cat.ids)
    assert cat.units and cat.source


def test_profiles_known_figures():
    p = load_catalog("profiles")
    assert {"2020", "2040", "3030", "4040", "4080"} <= set(p.ids)
    p2020, p4040 = p.get("2020"), p.get("4040")
    assert p2020.linear_mass == 0.5 and p2020.area == pytest.approx(182.8e-6)
    assert p4040.linear_mass == 1.74 and p4040.ix == pytest.approx(10.5e-8) and p4040.iy == p4040.ix
    rho = load_catalog("materials").get("aluminium_6063").density
    for prof in p:
        # linear mass = area * density for a solid-material section, within vendor scatter (5 %)
        assert prof.linear_mass == pytest.approx(prof.area * rho, rel=0.05), prof.id


def test_servo_figures():
    s = load_catalog("servos").get("XL330-M288-T")
    assert (s.mass, s.stall_torque, s.coulomb_friction, s.reflected_inertia) == (0.018, 0.52, 0.0128, 0.0018)


def test_unknown_entry_lists_ids():
    with pytest.raises(CatalogError, match=r"profiles entry '9090' does not exist. Available: 2020, 2040"):
        load_catalog("profiles").get("9090")


def test_unknown_kind():
    with pytest.raises(CatalogError, match="Available kinds: arms, materials"):
        load_catalog("bolts")


def test_number_without_unit_is_rejected(tmp_path):
    (tmp_path / "materials.yaml").write_text(
        "version: 1\nkind: materials\nunits: {density: kg/m^3}\nsource: test\n"
        "entries:\n  - {id: a, density: 1.0, youngs_modulus: 2.0, yield_strength: 3.0}\n"
    )
    with pytest.raises(CatalogError, match="'youngs_modulus' is a number without a declared unit"):
        load_catalog("materials", str(tmp_path))


def test_files_exist():
    for part in load_catalog("parts"):
        assert part_fragment_path(part).is_file()
    for arm in load_catalog("arms"):
        assert arm_model_path(arm.id).is_file()
    assert len(load_catalog("shelf")) == 12


def test_a_number_yaml_reads_as_text_is_rejected(tmp_path):
    # YAML 1.1 reads 7.0e10 (no exponent sign) as a string; a catalog number must be a number
    (tmp_path / "materials.yaml").write_text(
        "version: 1\nkind: materials\nunits: {density: kg/m^3, youngs_modulus: Pa, yield_strength: Pa}\n"
        "source: test\nentries:\n  - {id: a, density: 1.0, youngs_modulus: 7.0e10, yield_strength: 3.0}\n"
    )
    with pytest.raises(CatalogError, match="'youngs_modulus' is not a number: '7.0e10'"):
        load_catalog("materials", str(tmp_path))
    assert load_catalog("materials").get("pla").youngs_modulus == 3.5e9


def test_rle_catalog_lists_kinds_and_prints_entries_with_units(capsys):
    import json

    from rle_tasks.cli import main

    assert main(["catalog"]) == 0
    out = capsys.readouterr().out
    assert all(kind in out for kind in catalog_kinds())
    assert main(["catalog", "springs"]) == 0
    out = capsys.readouterr().out
    assert "rate [N/m]" in out and "max_force [N]" in out and "cs-d2.5-D20-n50" in out and "Shigley" in out
    assert main(["catalog", "springs", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["units"]["rate"] == "N/m" and len(data["entries"]) == len(load_catalog("springs"))
    assert main(["catalog", "bolts"]) == 2
    assert "catalog.unknown_kind" in capsys.readouterr().err
