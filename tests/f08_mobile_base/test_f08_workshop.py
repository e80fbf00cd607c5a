"""Issue-45 regressions on 08: parts of the base inside one another, and the public workshop check."""

import shutil

from lxml import etree

from rle_design.mjcf import load_design
from rle_tasks.core.solutions import materialise
from rle_tasks.f08_mobile_base.public.workshop import main, workshop_findings_of
from rle_tasks.f08_mobile_base.validity import check_validity


def _edited(tmp_path, edit):
    d = shutil.copytree(materialise("08-mobile-base", "reference"), tmp_path / "sub")
    path = d / "robot.xml"
    tree = etree.parse(str(path))
    edit(tree.getroot())
    tree.write(str(path))
    return d


def _battery_into_the_frame(root):
    # the reference battery (x -0.24..-0.04, bolted to the face of the cross member at x -0.04..0)
    # moved 20 mm forward: its box then reaches 20 mm into the cross member it is welded to
    battery = next(b for b in root.iter("body") if b.get("name") == "battery")
    x, y, z = (float(v) for v in battery.get("pos").split())
    battery.set("pos", f"{x + 0.02} {y} {z}")


def test_the_reference_base_passes_the_workshop_check(capsys):
    d = materialise("08-mobile-base", "reference")
    design = load_design(d)
    assert workshop_findings_of(design.fresh_spec(), design.compile()) == []
    assert main([str(d / "robot.xml")]) == 0 and "workshop check passed" in capsys.readouterr().out


def test_a_battery_sunk_into_the_frame_is_refused_by_name(tmp_path, capsys):
    d = _edited(tmp_path, _battery_into_the_frame)
    found = [(c, m) for c, m in check_validity(load_design(d)) if c == "f08.interpenetration"]
    assert [m.split(" (welded")[0] for _, m in found] == [
        "part 'profile_4040_cross_1' of body 'chassis' is sunk 20.0 mm into 'battery_geom' of body 'battery'"
    ]
    assert found[0][1].endswith("of shared material) at the zero pose")
    # the public helper reports the same, with a non-zero exit
    assert main([str(d / "robot.xml")]) == 1
    assert "f08.interpenetration: " in capsys.readouterr().out
