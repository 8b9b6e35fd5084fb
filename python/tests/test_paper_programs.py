"""The paper's own programs (App. B.1–B.6 and Fig. 8), copied verbatim with only the import line
added, run under `fabkit run` and give the same solved result as the bundled YAML examples."""

import json
import pathlib
import re
import runpy

import pytest

from conftest import PROGRAMS, SOURCE_DIR
from fabkit.hacks import Assembly

CASES = {
    "b1_toothbrush_holder": "toothbrush_holder",
    "b2_charger_holder": "charger_holder",
    "b3_soap_bottle_holder": "soap_bottle_holder",
    "b4_mug_hanger": "mug_hanger",
    "b5_paper_towel_holder": "paper_towel_holder",
    "b6_diaper_caddy": "diaper_caddy",
    "fig8_basket_between_rods": "basket_between_rods",
}


def program_assembly(name):
    """Runs a program in-process and returns the Assembly it built."""
    scope = runpy.run_path(str(PROGRAMS / f"{name}.py"))
    found = [v for v in scope.values() if isinstance(v, Assembly)]
    assert len(found) == 1, f"{name} should build exactly one Assembly"
    return found[0]


@pytest.mark.parametrize("program", sorted(CASES))
def test_program_runs_under_fabkit_run(program, fabkit_cli):
    fabkit_cli("run", PROGRAMS / f"{program}.py")


@pytest.mark.parametrize("program,example", sorted(CASES.items()))
def test_program_matches_bundled_example(program, example, fabkit_cli, tmp_path):
    result = program_assembly(program).solve()
    # Not yet at rest once parts may not pass through each other (docs/gallery.md): the CLI
    # says so (exit 3: infeasible as found) and writes its result all the same; Python agrees.
    not_yet_at_rest = example == "diaper_caddy"
    p = fabkit_cli("solve", SOURCE_DIR / "examples" / "hacks" / f"{example}.yaml", "-q", "-o", tmp_path,
                   check=not not_yet_at_rest)
    if not_yet_at_rest:
        assert p.returncode == 3, p.stdout + p.stderr
        assert "no configuration was found that keeps them apart" in p.stderr
    expected = json.loads((tmp_path / "result.json").read_text())
    assert result.stable == expected["stable"] is (not not_yet_at_rest)
    assert result.feasible == expected["feasible"] is (not not_yet_at_rest)
    pos, rot = result.target_error
    assert pos == pytest.approx(expected["target"]["pos_error_mm"], abs=1e-3)
    assert rot == pytest.approx(expected["target"]["rot_error_deg"], abs=1e-3)
    # Same parts in the same order, at the same places (names differ: the YAML names its parts).
    frames = list(result.frames.values())
    assert len(frames) == len(expected["parts"])
    for got, want in zip(frames, expected["parts"]):
        assert got.pos == pytest.approx(want["frame"]["pos"], abs=1e-3)
        for a, b in zip(got.rot, want["frame"]["rot"]):
            assert abs((a - b + 180) % 360 - 180) < 1e-3
    assert result.part_types == [p["type"] for p in expected["parts"]]


def paper_listings():
    """The programs as printed in the paper (App. B and Fig. 8, figure line numbers removed)."""
    text = (SOURCE_DIR.parent / "shared" / "papers" / "fabhacks.txt").read_text()
    appb = text[text.index("## B PROGRAMS FOR GALLERY EXAMPLES"):text.index("## C ADDITIONAL")]
    sections = re.split(r"\n#{2,3} (B\.\d) ", appb)
    listings = {}
    for key, body in zip(sections[1::2], sections[2::2]):
        blocks = re.findall(r"```\n(.*?)```", body, re.S)
        listings[key] = "\n".join(b.strip("\n") for b in blocks if b.strip())
    start = text.index("1  assembly = Assembly()")
    fig8 = text[start:text.index("```", start)].rstrip("\n").split("\n")
    listings["Fig. 8"] = "\n".join(re.sub(r"^\d+\s*", "", line) for line in fig8)
    return listings


def test_programs_are_verbatim_copies_of_the_paper():
    paper = SOURCE_DIR.parent / "shared" / "papers" / "fabhacks.txt"
    # The paper is the test's data: without it the test fails, it never passes by skipping.
    assert paper.exists(), f"{paper} must be beside the project to check the programs"
    listings = paper_listings()
    keys = {"b1": "B.1", "b2": "B.2", "b3": "B.3", "b4": "B.4", "b5": "B.5", "b6": "B.6", "fig8": "Fig. 8"}
    for program in CASES:
        lines = (PROGRAMS / f"{program}.py").read_text().split("\n")
        assert lines[0].startswith("from fabkit.hacks import *")
        body = "\n".join(lines[2:]).rstrip("\n")
        assert body == listings[keys[program.split("_")[0]]], program
