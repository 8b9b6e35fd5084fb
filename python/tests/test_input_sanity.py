"""Input sanity in the Python API: absurd or non-finite positions are refused with the part
and the quantity named, and a multi-primitive Environment({...}) places every primitive."""

import struct

import pytest

import fabkit
from fabkit.hacks import *


def stl_vertices(path):
    data = path.read_bytes()
    (count,) = struct.unpack_from("<I", data, 80)
    assert len(data) == 84 + 50 * count
    vertices = []
    for i in range(count):
        floats = struct.unpack_from("<12f", data, 84 + 50 * i)
        vertices += [floats[3:6], floats[6:9], floats[9:12]]
    return vertices


@pytest.mark.parametrize("pos", [[2e6, 0, 0], [0, -1.5e6, 0], [0, 0, 1e9]])
def test_absurd_positions_are_refused_naming_the_part(pos):
    assembly = Assembly()
    with pytest.raises(fabkit.InputError, match=r"add ClosetRods: frame .* is absurd: positions are in mm and may be at most 1e\+06 mm"):
        assembly.add(ClosetRods(), Frame(pos, [0, 0, 0]))
    rods = Environment({"left": Rod({"length": 170, "radius": 6.35}), "right": Rod({"length": 170, "radius": 6.35})})
    with pytest.raises(fabkit.InputError, match=r"add Environment\.left: frame .* is absurd"):
        assembly.add(rods.left, Frame(pos, [0, 0, 0]))
    assert assembly.part_count == 0
    assembly.add(ClosetRods(), Frame([1e6, 0, 0], [0, 0, 0]))  # 1 km is still a place
    assert assembly.part_count == 1


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_positions_are_refused(bad):
    with pytest.raises(ValueError, match="Frame pos has a non-finite value"):
        Frame([0, bad, 0], [0, 0, 0])
    with pytest.raises(ValueError, match="Frame rot has a non-finite value"):
        Frame([0, 0, 0], [bad, 0, 0])


def test_multi_primitive_environment_places_every_primitive(tmp_path):
    rods = Environment({"left": Rod({"length": 170, "radius": 6.35}), "right": Rod({"length": 170, "radius": 6.35})})
    assembly = Assembly()
    assembly.add(rods.left, Frame([0, -600, 200], [90, 0, 90]))
    left_hook, right_hook = DoubleHook(), DoubleHook()
    assembly.connect(left_hook.hook2, rods.left)
    with pytest.raises(fabkit.ConnectError, match=r"Environment\.right is not placed yet; add it first"):
        assembly.connect(right_hook.hook2, rods.right)
    assembly.add(rods.right, Frame([0, 600, 200], [90, 0, 90]))
    with pytest.raises(fabkit.InputError, match="that primitive is already placed"):
        assembly.add(rods.right, Frame([0, 0, 0], [0, 0, 0]))
    assembly.connect(right_hook.hook2, rods.right)
    assert assembly.part_count == 3  # one environment, two hooks
    result = assembly.solve()
    result.save_all(tmp_path)
    vertices = stl_vertices(tmp_path / "assembly.stl")
    xs = [v[0] for v in vertices]
    ys = [v[1] for v in vertices]
    # Both rods where they were added (170 mm long along x at y = ±600), the hooks on them;
    # nothing at the origin, where an unplaced rod would be drawn.
    assert min(xs) == pytest.approx(-85, abs=1e-3)
    assert max(xs) == pytest.approx(85, abs=1e-3)
    assert any(y < -590 for y in ys) and any(y > 590 for y in ys)
    assert all(abs(y) > 580 for y in ys)
