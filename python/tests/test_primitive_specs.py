"""One primitive-spec parser behind every entry point: the same spec given to Python
(Rod({...})), to a design file (an environment's primitives) and to a part file gives the same
primitive — or the same error."""

import subprocess

import pytest
from fabkit import InputError
from fabkit.hacks import Environment, Hook, Rod, Ring, Surface, Tube, load_design, load_parts

CONSTRUCTORS = {"rod": Rod, "hook": Hook, "ring": Ring, "surface": Surface, "tube": Tube}

GOOD = [
    {"type": "rod", "radius": 5, "length": 500},
    {"type": "rod", "radius": 5, "length": 500, "centerline": True, "is_open": False},
    {"type": "hook", "arc_radius": 19, "arc_angle": 210, "thickness": 5, "flex": True,
     "theta_range": [0, 200], "frame": {"pos": [0, 0, -54.2], "rot": [90, 0, 0]}},
    {"type": "ring", "arc_radius": 14.82, "thickness": 4.5, "flex": True, "phi_range": [40, 140]},
    {"type": "tube", "inner_radius": 8.5, "thickness": 1.5, "length": 387, "open_ends": [True, False]},
    {"type": "surface", "width": 400, "length": 400},
]
BAD = [
    ({"type": "rod", "radius": 5, "length": 500, "flex": True}, "unknown key 'flex'"),
    ({"type": "rod", "radius": 5, "length": 500, "theta_range": [0, 90]}, "unknown key 'theta_range'"),
    ({"type": "hook", "arc_radius": 5, "arc_angle": 400, "thickness": 1}, "arc angle 400° must be in (0, 360]"),
    ({"type": "rod", "radius": -5, "length": 500}, "rod radius -5 mm must be positive"),
    ({"type": "ring", "arc_radius": 2, "thickness": 3}, "wire radius 3 mm must be smaller than its arc radius 2 mm"),
    ({"type": "hook", "arc_radius": 19, "arc_angle": 210, "thickness": 5, "theta_range": [90, 10]},
     "theta_range [90, 10] is not an interval"),
]


def yaml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k}: {yaml_value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(yaml_value(x) for x in v) + "]"
    return repr(v)


def via_python(spec):
    params = {k: v for k, v in spec.items() if k != "type"}
    env = Environment({"p": CONSTRUCTORS[spec["type"]](params)})
    return env.primitive_spec("p")


def via_design_file(spec, tmp_path):
    path = tmp_path / "design.yaml"
    path.write_text("fabkit: hacks/1\nenvironment:\n"
                    f"  - {{name: env, primitives: {{p: {yaml_value(spec)}}}}}\n")
    design = load_design(path)
    return design.parts["env"].primitive_spec("p")


def via_part_file(spec, tmp_path, name):
    path = tmp_path / f"{name}.yaml"
    entry = dict(spec, name="p")
    path.write_text(f"parts:\n  - name: {name}\n    mass: 100\n    primitives:\n      - {yaml_value(entry)}\n")
    load_parts(path)
    import fabkit.hacks as h
    return getattr(h, name)().primitive_spec("p")


@pytest.mark.parametrize("index", range(len(GOOD)))
def test_the_same_spec_gives_the_same_primitive_everywhere(index, tmp_path):
    spec = GOOD[index]
    a = via_python(spec)
    b = via_design_file(spec, tmp_path)
    c = via_part_file(spec, tmp_path, f"SpecPart{index}")
    assert a == b == c
    for key, value in spec.items():
        if key == "frame":
            assert a["pos"] == value["pos"] and a["rot"] == value["rot"]
        elif key != "type":
            assert a[key] == value, key


@pytest.mark.parametrize("index", range(len(BAD)))
def test_the_same_bad_spec_gives_the_same_error_everywhere(index, tmp_path):
    spec, message = BAD[index]
    errors = []
    for attempt in (lambda: via_python(spec),
                    lambda: via_design_file(spec, tmp_path),
                    lambda: via_part_file(spec, tmp_path, f"BadPart{index}")):
        with pytest.raises(InputError) as e:
            attempt()
        errors.append(str(e.value))
    for text in errors:
        assert message in text, errors
