"""fabkit.flatpack: the paper's Fig. 3 program, its outputs read back by independent tools
(ezdxf for DXF, an XML parser for SVG, a plain STL edge check), and errors as exceptions."""

import collections
import json
import os
import pathlib
import re
import runpy
import struct
import xml.etree.ElementTree as ET

import ezdxf
import pytest

import fabkit
from conftest import PROGRAMS, SOURCE_DIR
from fabkit.flatpack import Component, FingerJoint, build_file, check_file

EXAMPLES = SOURCE_DIR / "examples" / "flatpack"


def svg_rings(path):
    """Every path of the cut layer as a list of (x, y) in mm, y flipped back to the sheet frame."""
    root = ET.parse(path).getroot()
    assert root.get("width").endswith("mm") and root.get("height").endswith("mm")
    w, h = float(root.get("width")[:-2]), float(root.get("height")[:-2])
    assert root.get("viewBox") == f"0 0 {root.get('width')[:-2]} {root.get('height')[:-2]}"
    ns = {"svg": "http://www.w3.org/2000/svg"}
    rings = []
    for g in root.findall("svg:g", ns):
        if g.get("id") != "cut":
            continue
        for p in g.findall("svg:path", ns):
            tokens = p.get("d").replace("M", " ").replace("L", " ").replace("Z", " ").split()
            xs = [float(t) for t in tokens]
            rings.append([(xs[i], h - xs[i + 1]) for i in range(0, len(xs), 2)])
    return (w, h), rings


def dxf_rings(path):
    doc = ezdxf.readfile(str(path))
    assert doc.header["$INSUNITS"] == 4  # millimetres
    rings, texts = [], []
    for e in doc.modelspace():
        if e.dxftype() == "LWPOLYLINE":
            assert e.closed, "every cut outline is a closed polyline"
            assert e.dxf.layer == "CUT"
            rings.append([(p[0], p[1]) for p in e.get_points("xy")])
        elif e.dxftype() == "TEXT":
            assert e.dxf.layer == "LABELS"
            assert all(ord(c) < 128 for c in e.dxf.text), "non-ASCII is escaped in the DXF"
            texts.append(dxf_text(e.dxf.text))
    return rings, texts


def dxf_text(text):
    """A DXF TEXT value as a CAD program shows it: \\U+XXXX escapes (how AutoCAD 2000 files
    carry characters outside their code page) decoded."""
    return re.sub(r"\\U\+([0-9A-Fa-f]{4})", lambda m: chr(int(m.group(1), 16)), text)


def bbox(ring):
    xs, ys = [p[0] for p in ring], [p[1] for p in ring]
    return max(xs) - min(xs), max(ys) - min(ys)


def stl_edges_paired(path):
    data = pathlib.Path(path).read_bytes()
    (n,) = struct.unpack_from("<I", data, 80)
    edges = collections.Counter()
    for k in range(n):
        v = struct.unpack_from("<12f", data, 84 + 50 * k)[3:]
        tri = [tuple(round(c, 4) for c in v[i:i + 3]) for i in (0, 3, 6)]
        for i in range(3):
            edges[(tri[i], tri[(i + 1) % 3])] += 1
    return n > 0 and all(edges[(b, a)] == c for (a, b), c in edges.items())


def test_fig3_program_runs_with_only_its_imports_changed(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    runpy.run_path(str(PROGRAMS / "fig3_connection_joint_builder.py"))
    out = tmp_path / "output" / "ConnectionJointBuilder"
    report = json.loads((out / "report.json").read_text())
    assert report["counts"]["pieces"] == 2
    assert report["joints"][0]["kind"] == "finger-finger"
    assert not report["joints"][0]["automatic"]
    # The saved design is a design file fabkit reads, with the same result.
    again = check_file(tmp_path / "library" / "ConnectionJointBuilder.yaml")
    assert again["counts"] == report["counts"]


def test_snake_case_twins_build_the_same_design():
    a = Component("pair")
    a.add_subcomponent("A", "Rectangle", l=30, w=60).add_subcomponent("B", "Rectangle", l=30, w=60)
    a.add_edge_to_edge(("A", "t"), ("B", "b"), angle=(90, 0, 0))
    b = Component("pair")
    b.addSubcomponent("A", "Rectangle", l=30, w=60).addSubcomponent("B", "Rectangle", l=30, w=60)
    b.addEdgeToEdge(("A", "t"), ("B", "b"), angle=(90, 0, 0))
    assert a.check()["pieces"] == b.check()["pieces"]


def test_errors_are_fabkit_exceptions_naming_the_quantity():
    c = Component()
    c.addSubcomponent("A", "Rectangle", l=30)
    with pytest.raises(fabkit.InputError, match="nothing determines A.w"):
        c.check()
    c = Component()
    c.addSubcomponent("A", "Rectangel", l=30, w=3)
    with pytest.raises(fabkit.Error, match="did you mean 'Rectangle'"):
        c.check()


@pytest.mark.parametrize("example", ["bookend", "reading_desk", "stool", "computer_desk",
                                     "simple_table", "picnic_table", "bookshelf", "bunk_bed",
                                     "tv_console", "box_with_lid"])
def test_sheets_read_back_at_the_model_size(example, tmp_path):
    report = build_file(EXAMPLES / f"{example}.yaml", tmp_path)
    sizes = sorted(tuple(p["size_mm"]) for p in report["pieces"])
    outer_svg, outer_dxf = [], []
    for k in range(1, report["sheets"]["count"] + 1):
        (w, h), svg = svg_rings(tmp_path / f"sheet-{k}.svg")
        assert (w, h) == (600, 400)
        dxf, texts = dxf_rings(tmp_path / f"sheet-{k}.dxf")
        assert len(svg) == len(dxf)
        # The two writers agree point for point (0.01 mm).
        for a, b in zip(svg, dxf):
            assert len(a) == len(b)
            for p, q in zip(a, b):
                assert abs(p[0] - q[0]) < 0.01 and abs(p[1] - q[1]) < 0.01
            assert all(-0.01 <= x <= 600.01 and -0.01 <= y <= 400.01 for x, y in a)
        pieces_here = [p for p in report["pieces"] if p["sheet"] == k]
        assert {p["name"] for p in pieces_here} <= set(texts)
        # Assembly marks name the piece that goes there, with the arrow intact.
        marks = [t for t in texts if t.startswith("→ ")]
        assert marks and {t[2:] for t in marks} <= {p["name"] for p in report["pieces"]}
        outer_svg += svg
        outer_dxf += dxf
    # Each piece's outline, as read back, has the model's size (in some allowed rotation).
    boxes = [bbox(r) for r in outer_dxf]
    for size in sizes:
        assert any((abs(b[0] - size[0]) < 0.01 and abs(b[1] - size[1]) < 0.01) or
                   (abs(b[1] - size[0]) < 0.01 and abs(b[0] - size[1]) < 0.01) for b in boxes), size
    assert stl_edges_paired(tmp_path / "model.stl")


def test_reading_desk_counts_through_python():
    r = check_file(EXAMPLES / "reading_desk.yaml")
    assert r["counts"]["components"] == 11
    assert r["counts"]["joints"] == 17
    assert r["counts"]["automatic_joints"] == 7


def test_cli_builds_a_flatpack_design(fabkit_cli, tmp_path):
    p = fabkit_cli("build", EXAMPLES / "reading_desk.yaml", "-o", tmp_path)
    assert "17 joints (10 from connections, 7 automatic" in p.stdout
    assert (tmp_path / "scene.glb").exists()


def test_composites_report_their_sub_designs_and_meta_parameters():
    r = check_file(EXAMPLES / "bunk_bed.yaml")
    names = {p["name"] for p in r["pieces"]}
    assert {"desk.top", "bed.deck", "ladder.stile_left"} <= names
    meta = {m["name"]: m for m in r["meta_parameters"]}
    assert meta["length"]["value"] == 300
    assert "desk.top.l" in meta["length"]["drives"] and "bed.deck.l" in meta["length"]["drives"]
    # A failed fabrication check is reported, not raised: the design was checked.
    locked = check_file(EXAMPLES / "picnic_table_locked.yaml")
    assert sorted(locked["not_insertable"]) == sorted(
        ["table.bench_front", "table.bench_back", "table.end_left", "table.end_right"])
    assert locked["assembly_order"] == []
    assert any("not assemblable: table.bench_front" in d["message"] for d in locked["diagnostics"])


def test_burn_test_sheet_reads_back_with_ezdxf_at_the_drawn_widths(fabkit_cli, tmp_path):
    """The burn-test DXF and SVG read by independent readers: the sheet's size, a label per
    cell, and each cell's fingers, dents and slot at the widths of Appendix A for its Δ and δ."""
    t, kerfs, fits = 3.0, [0.05, 0.1, 0.15], [0.0, 0.1]
    fabkit_cli("flatpack", "burn-test", "--thickness", t, "--kerf", "0.05:0.15:0.05",
               "--interference", "0,0.1", "-o", tmp_path)
    (w, h), svg = svg_rings(tmp_path / "burn-test.svg")
    assert (w, h) == (5 + 2 * 63 + 10 + 5, 5 + 3 * 32 + 2 * 10 + 5)
    rings, texts = dxf_rings(tmp_path / "burn-test.dxf")
    assert len(rings) == len(svg) == 2 * len(kerfs) * len(fits)
    assert sorted(texts) == sorted(f"Δ {k:g} δ {f:g}" for k in kerfs for f in fits)

    def runs(ring, y):
        """Lengths of the horizontal edges of `ring` at height y (to 1 µm)."""
        out = []
        for (x0, y0), (x1, y1) in zip(ring, ring[1:] + ring[:1]):
            if abs(y0 - y) < 1e-3 and abs(y1 - y) < 1e-3:
                out.append(round(abs(x1 - x0), 6))
        return out

    # Rings sorted into cells: a comb (lower) and a dent strip (upper) per cell, in the order
    # the labels give (rows by Δ from the bottom, columns by δ).
    def corner(r):
        return (min(p[1] for p in r), min(p[0] for p in r))
    combs = sorted((r for r in rings if len(r) == 4 * 3 + 4), key=corner)
    strips = sorted((r for r in rings if r not in combs), key=corner)
    assert len(combs) == len(strips) == len(kerfs) * len(fits)
    k = 0
    for kerf in kerfs:
        for fit in fits:
            comb, strip = combs[k], strips[k]
            k += 1
            top = max(p[1] for p in comb)
            finger = 3 * t + (4 * kerf + fit) / 2
            assert runs(comb, top) == pytest.approx([finger] * 3, abs=1e-5)
            bottom = min(p[1] for p in strip)
            dent = 3 * t - (4 * kerf + fit) / 2
            # The dents' inner ends, one board up from the strip's open edge.
            assert runs(strip, bottom + t) == pytest.approx([dent] * 3, abs=1e-5)
            # The slot's closed end, two boards up.
            slot = t - 2 * kerf - fit
            assert runs(strip, bottom + 2 * t) == pytest.approx([slot], abs=1e-5)
            # Cut with kerf Δ per side: the finger is δ wider than its dent, the slot δ
            # narrower than the board.
            assert (finger - 2 * kerf) - (dent + 2 * kerf) == pytest.approx(fit, abs=1e-9)
            assert slot + 2 * kerf == pytest.approx(t - fit, abs=1e-9)
