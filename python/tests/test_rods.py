"""fabkit.rods: the RodSteward kit from Python."""

import json
import math
import pathlib

import pytest

import fabkit
from fabkit.rods import Structure, plan_cuts, rod_materials, tolerance_board

from conftest import SOURCE_DIR

EXAMPLES = SOURCE_DIR / "examples" / "rods"

TETRA = dict(nodes=[[0, 0, 0], [300, 0, 0], [150, 260, 0], [150, 87, 250]],
             edges=[(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)])


def test_offsets_and_lengths_follow_appendix_a():
    # Two rods at 90° and a leaf: g = r + ε at the right angle, 0 at the leaves.
    s = Structure(nodes=[[0, 0, 0], [200, 0, 0], [0, 200, 0]], edges=[(0, 1), (0, 2)],
                  radius=5, tolerance=0.2)
    r = s.check()
    assert r.rods[0].offsets == pytest.approx((5.2, 0.0))
    assert r.rod_lengths["rod 01-02"] == pytest.approx(200 - 5.2)
    assert r.rods[0].angles[0] == pytest.approx(90)


def test_check_returns_findings_not_exceptions():
    crossing = Structure.from_file(EXAMPLES / "failing" / "rods_intersect.yaml")
    r = crossing.check()
    assert not r.passed
    assert [f.code for f in r.errors] == ["rods-intersect"]
    assert r.errors[0].kind == "check"
    assert "rod 03-04 and rod 05-06 intersect" in r.errors[0].message
    assert r.termination == "built-with-findings"


def test_check_reports_balance_cut_plan_structure_and_assembly():
    r = Structure(**TETRA, diameter=6.35).check()
    assert r.passed, [str(f) for f in r.findings]
    assert r.balance.stands and r.balance.margin > 0
    assert r.balance.ground_joints == [1, 2, 3]
    assert r.cut_plan.proven_optimal
    assert sum(len(s) for s in r.cut_plan.stock) == 6
    assert r.structure["solved"]
    assert len(r.assembly) == 4 + 6
    assert r.assembly[0].kind == "joint" and r.assembly[1].kind == "rod"


def test_build_makes_watertight_engraved_joints_and_saves(tmp_path):
    r = Structure(**TETRA, diameter=6.35, wall=2, socket=12).build()
    assert r.termination == "built"
    assert all(j.watertight for j in r.joints)
    assert [j.label for j in r.joints] == ["01", "02", "03", "04"]
    assert all(j.engraving["removed_mm3"] > 0 for j in r.joints)
    vertices, faces = r.joints[3].mesh()
    assert len(faces) > 100
    files = r.save(tmp_path / "out")
    names = sorted(pathlib.Path(f).name for f in files)
    assert "joint_04.stl" in names and "joints.3mf" in names and "scene.glb" in names
    assert "cut_plan.svg" in names and "cut_list.csv" in names and "assembly.json" in names
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert report["joints"][0]["watertight"]


def test_bad_input_raises_input_error_with_the_reason():
    with pytest.raises(fabkit.InputError, match="edge 1 joins node 0 to itself"):
        Structure(nodes=[[0, 0, 0], [1, 0, 0]], edges=[(0, 0)])
    with pytest.raises(fabkit.InputError, match="node 2 at .* is not joined"):
        Structure(nodes=[[0, 0, 0], [100, 0, 0], [5, 5, 5]], edges=[(0, 1)])
    with pytest.raises(fabkit.InputError, match="rod radius r is -1"):
        Structure(**TETRA, radius=-1)
    with pytest.raises(TypeError, match="did you mean 'tolerance'"):
        Structure(**TETRA, tolerence=0.1)
    with pytest.raises(ValueError, match="unknown rod material 'balsa'"):
        Structure(**TETRA, rod_material="balsa")
    with pytest.raises(fabkit.InputError, match="d.yaml:3:"):
        Structure.from_text("fabkit: rods/1\nname: x\nrod: {radius: .nan}\nnodes: [[0,0,0],[1,0,0]]\nedges: [[1,2]]\n", "d.yaml")


def test_build_of_an_impossible_design_raises_infeasible():
    s = Structure.from_file(EXAMPLES / "failing" / "rod_longer_than_stock.yaml")
    with pytest.raises(fabkit.InfeasibleError, match="longer than the usable stock length 894.4 mm"):
        s.build()
    assert not s.check().passed  # check() still reports it


def test_scaling_keeps_the_joints():
    big = Structure.from_file(EXAMPLES / "lamp_1400.yaml")
    small = big.scaled(0.5)
    assert len(small.reused_joints(big)) == len(big.nodes)
    looser = small.with_parameters(tolerance=0.3)
    assert looser.reused_joints(big) == []
    assert small.check().rods[0].length < 0.6 * big.check().rods[0].length


def test_loads_tip_a_table_missing_a_leg():
    table = Structure.from_file(EXAMPLES / "coffee_table.yaml")
    nodes = [p for i, p in enumerate(table.nodes) if i != 7]
    edges = [(a if a < 7 else a - 1, b if b < 7 else b - 1) for a, b in table.edges if 7 not in (a, b)]
    three = Structure(nodes=nodes, edges=edges, diameter=12.7, wall=3, socket=25)
    assert three.check().balance.stands
    three.add_load(3, [0, 0, -20])
    r = three.check()
    assert not r.balance.stands
    assert "unbalanced" in [f.code for f in r.errors]


def test_plan_cuts_and_tolerance_board(tmp_path):
    plan = plan_cuts([("a", 489), ("b", 489), ("c", 300)], stock_length=1000, end_padding=10, kerf=2)
    assert plan.stock_count == 2 and plan.proven_optimal
    assert plan.stock[0] == [("a", 10.0, 489.0), ("b", 501.0, 489.0)]
    assert 'width="1010mm"' in plan.svg
    with pytest.raises(fabkit.InfeasibleError, match="'x' is 1200 mm long"):
        plan_cuts([("x", 1200)], stock_length=1000)
    tolerances = tolerance_board(tmp_path / "board.stl", -0.1, 0.2, 0.1, diameter=6.35)
    assert tolerances == pytest.approx([-0.1, 0.0, 0.1, 0.2])
    assert (tmp_path / "board.stl").stat().st_size > 1000


def test_preview_is_meshes_without_booleans():
    p = Structure(**TETRA).preview()
    assert len(p["joints"]) == 4 and len(p["rods"]) == 6
    assert len(p["rod_lengths"]) == 6
    assert "hardwood" in rod_materials()
