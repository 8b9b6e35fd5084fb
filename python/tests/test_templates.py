"""fabkit.templates from Python: compose, reshape (every constraint holds), connect, stability,
bill of materials, build, errors."""

import pathlib

import pytest

import fabkit
from fabkit import templates

from conftest import SOURCE_DIR


def table_with_shelf():
    m = templates.Model("table with a bottom shelf")
    m.add("dining_table", as_="table")
    m.add("bookshelf/shelves/bottom_shelf", as_="shelf", at=[0, 0, 40], snap=False, connect=False)
    m.set("shelf", "size_y", 789)
    return m


def test_database_lists_the_bundled_designs():
    db = templates.Database.bundled()
    assert len(db.names()) >= 12
    assert "dining_table" in db.names()
    assert len(db.catalog) >= 120
    assert db.catalog.find("LUM-PINE-2x4")["dims"][0] == (3658.0, True)
    assert "leg_fl" in db.describe("dining_table/base/legs")


def test_compose_and_reshape_keeps_every_constraint():
    m = templates.Model()
    m.add("dining_table", as_="table")
    report = m.add("bookshelf/shelves/bottom_shelf", as_="shelf", at=[0, 0, 40])
    assert report["snapped_planes"] >= 1
    m2 = templates.load(SOURCE_DIR / "examples" / "templates" / "table_with_shelf.yaml")
    for target in (1700, 1300, 1500):
        r = m2.set("table/base/legs", "size_x", target)
        assert r["reached"], r["message"]
        assert m2.max_violation() < 1e-9
    r = m2.drag("table", "size_z", 40)
    assert 30 < r["achieved"] - 760 <= 40
    assert m2.max_violation() < 1e-9
    assert m2.controls("top")["size_z"]["hidden"]       # plywood thickness is fixed
    assert not m2.controls("top")["size_x"]["hidden"]


def test_unreachable_request_names_the_binding_constraint():
    m = templates.load(SOURCE_DIR / "examples" / "templates" / "table_with_shelf.yaml")
    r = m.set("leg_fl", "size_z", 5000)
    assert not r["reached"]
    assert "longest stock" in r["message"]
    assert m.max_violation() < 1e-9


def test_bom_stability_and_build(tmp_path):
    m = templates.load(SOURCE_DIR / "examples" / "templates" / "table_with_shelf.yaml")
    bom = m.bom()
    assert bom["total"] == pytest.approx(sum(line["total"] for line in bom["lines"]))
    assert any(line["item"] == "LBR-40" and line["parts"] == 4 for line in bom["lines"])
    assert m.stability()["stable"]
    out = m.build(tmp_path / "out")
    assert out["verdict"] == "feasible"
    for name in ("bom.csv", "report.html", "scene.glb", "model.stl"):
        assert (tmp_path / "out" / name).exists()


def test_a_leg_removed_tips_under_a_lean():
    m = templates.Model()
    m.add("dining_table", as_="table")
    lean = [("top", [780, 430, 750], [0, 0, -200])]
    assert m.stability(loads=lean)["stable"]
    m.remove("leg_br")
    s = m.stability(loads=lean)
    assert not s["stable"]
    assert any("tips" in msg for msg in s["messages"].splitlines())


def test_errors_are_fabkit_errors():
    m = templates.Model()
    with pytest.raises(fabkit.InputError, match="did you mean 'dining_table'"):
        m.add("dinning_table")
    m.add("dining_table", as_="table")
    with pytest.raises(fabkit.InputError, match="no node 'tabel'"):
        m.set("tabel", "size_x", 1000)
    with pytest.raises(ValueError, match="unknown control"):
        m.set("table", "width", 1000)
    with pytest.raises(fabkit.InfeasibleError, match="no connection found between 'caster_fl' and 'top'"):
        m.add("rolling_cart/wheels/caster_fl", as_="caster", at=[0, 0, 800], snap=False)
    assert m.part_count == 61  # the failed add left the model unchanged
    with pytest.raises(fabkit.InputError, match="cannot read model file"):
        templates.load("/nonexistent/model.yaml")


def test_reshape_example_program(tmp_path, fabkit_cli):
    p = fabkit_cli("run", SOURCE_DIR / "examples" / "templates" / "reshape_table.py", tmp_path / "out")
    assert "largest violation" in p.stdout
    assert "stable" in p.stdout
    assert (tmp_path / "out" / "bom.csv").exists()
