"""No input crashes the interpreter, files are read and written safely, and time limits hold.

Random calls run in a child interpreter, so a crash fails the test with its last call instead
of killing pytest."""

import os
import pathlib
import subprocess
import sys
import textwrap
import time

import pytest

import fabkit
from fabkit import _fabkit
from fabkit import flatpack, hacks, rods, templates

from conftest import SOURCE_DIR

EXAMPLES = SOURCE_DIR / "examples"
MODULE_DIR = pathlib.Path(_fabkit.__file__).parents[1]


def bound_classes():
    found = []

    def walk(mod, prefix, depth=0):
        for name in sorted(dir(mod)):
            obj = getattr(mod, name)
            if isinstance(obj, type) and not issubclass(obj, BaseException) and \
                    "pybind11_object" in [b.__name__ for b in obj.__mro__]:
                found.append((prefix + name, obj))
            elif type(obj).__name__ == "module" and obj.__name__.startswith("fabkit._fabkit") and depth < 2:
                walk(obj, prefix + name + ".", depth + 1)

    walk(_fabkit, "")
    return found


def run_child(code, cwd, timeout=240):
    env = dict(os.environ, PYTHONPATH=str(MODULE_DIR) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


@pytest.mark.parametrize("name", [n for n, _ in bound_classes()])
def test_new_without_init_never_makes_a_broken_instance(name, tmp_path):
    # Cls.__new__(Cls) (what copy and pickle do) either refuses or gives a whole object; then
    # every method and property of it is used. Before: segfaults for seven classes.
    code = f"""
    import copy
    import fabkit._fabkit as F
    cls = F
    for part in {name!r}.split("."):
        cls = getattr(cls, part)
    try:
        obj = cls.__new__(cls)
    except TypeError as e:
        assert "cannot be created directly" in str(e) or "argument" in str(e) or "missing" in str(e), e
        print("refused")
    else:
        for attr in dir(obj):
            if attr.startswith("__") and attr not in ("__repr__", "__len__"):
                continue
            try:
                v = getattr(obj, attr)
                if callable(v):
                    v()
            except Exception:
                pass
        print("whole")
    try:
        copy.copy(cls.__new__(cls))
    except Exception:
        pass
    """
    p = run_child(code, tmp_path)
    assert p.returncode == 0, f"{name}: exit {p.returncode}\n{p.stdout}\n{p.stderr[-2000:]}"
    assert p.stdout.strip() in ("refused", "whole")


def test_classes_without_a_constructor_say_how_to_get_one():
    with pytest.raises(TypeError, match="cannot be created directly"):
        _fabkit.rods.Result.__new__(_fabkit.rods.Result)
    with pytest.raises(TypeError, match="cannot be created directly"):
        _fabkit.rods.Result()
    # Classes with a constructor still construct, and a model still works.
    m = _fabkit.templates.Model("m")
    assert m.name == "m"
    assert _fabkit.Frame([1, 2, 3]).pos == [1, 2, 3]
    assert _fabkit.hacks.Assembly().part_count == 0


RANDOM_CALLS = """
import math, random, sys, traceback
import fabkit, fabkit._fabkit as F
from fabkit import flatpack, hacks, rods, templates

rng = random.Random(SEED)
values = [None, 0, 1, -1, 7, 2**63, -2**70, 0.5, 1e308, -1e-300, math.nan, math.inf, -math.inf,
          True, "", "x", "DoubleHook", "hook1", "rod", "bookshelf", "flip", "\\udcff", "é" * 3,
          "a" * 5000, "../x", "nul\\0byte", b"bytes", bytearray(b"\\xff"), [], [0, 0, 0],
          [1, 2], [[0, 0, 0], [100, 0, 0], [0, 100, 0]], [(0, 1), (1, 2)], [math.nan] * 3, {},
          {"length": 5}, {"extended_length": -4}, (0, 1), object(), float, lambda: 1]

def instances():
    out = []
    for make in (lambda: F.Frame(), lambda: F.hacks.Assembly(), lambda: F.hacks.make_part("DoubleHook"),
                 lambda: F.hacks.make_part("DoubleHook").hook1, lambda: F.hacks.make_primitive("rod"),
                 lambda: F.rods.Parameters(), lambda: F.templates.Model("m"),
                 lambda: F.templates.Database.bundled(), lambda: F.templates.Catalog.bundled(),
                 lambda: hacks.Assembly(), lambda: flatpack.Component("c"),
                 lambda: rods.Structure(nodes=[[0, 0, 0], [300, 0, 0], [0, 300, 0]], edges=[(0, 1), (1, 2), (2, 0)])):
        try:
            out.append(make())
        except Exception:
            pass
    return out

pool = values + instances()
targets = []
for mod in (F, F.hacks, F.rods, F.flatpack, F.templates, hacks, flatpack, rods, templates):
    for name in dir(mod):
        if name.startswith("_") or name in ("sweep", "solve_many", "tolerance_board"):
            continue
        obj = getattr(mod, name)
        if callable(obj) and not (isinstance(obj, type) and issubclass(obj, BaseException)):
            targets.append((f"{mod.__name__}.{name}", obj))
for obj in instances():
    for name in dir(obj):
        if name.startswith("_") or name in ("save", "save_all", "build", "makeOutput", "make_output"):
            continue
        try:
            attr = getattr(obj, name)
        except Exception:
            continue
        if callable(attr):
            targets.append((f"{type(obj).__name__}.{name}", attr))

calls = 0
for i in range(CALLS):
    label, f = rng.choice(targets)
    args = [rng.choice(pool) for _ in range(rng.randint(0, 4))]
    sys.stderr.write(f"call {i}: {label}{tuple(repr(a)[:40] for a in args)}\\n")
    sys.stderr.flush()
    try:
        r = f(*args)
        if callable(getattr(r, "__repr__", None)):
            repr(r)
    except (fabkit.Error, TypeError, ValueError, KeyError, IndexError, AttributeError, OverflowError,
            RuntimeError, OSError, UnicodeError, NotImplementedError, RecursionError) as e:
        str(e)
    calls += 1
print("calls", calls)
"""


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_random_calls_raise_python_errors_never_crash(seed, tmp_path):
    # 4 × 1500 calls of every function and method with hostile arguments (NaN, huge numbers,
    # lone surrogates, NUL bytes, wrong types, objects of other classes).
    code = RANDOM_CALLS.replace("SEED", str(seed)).replace("CALLS", "1500")
    p = run_child(code, tmp_path, timeout=600)
    last = [l for l in p.stderr.splitlines() if l.startswith("call ")][-1:] or ["(none)"]
    assert p.returncode == 0, f"exit {p.returncode} at {last[0]}\n{p.stderr[-3000:]}"
    assert "calls 1500" in p.stdout


# ---- files ----------------------------------------------------------------------------------

def test_design_files_must_be_regular_and_bounded(tmp_path):
    fifo = tmp_path / "design.yaml"
    os.mkfifo(fifo)
    started = time.monotonic()
    for path in ["/dev/zero", str(fifo), str(tmp_path)]:
        with pytest.raises(fabkit.InputError, match="not a regular file|directory"):
            flatpack.check_file(path)
    with pytest.raises(fabkit.InputError, match="no such file"):
        flatpack.check_file(tmp_path / "missing.yaml")
    big = tmp_path / "big.yaml"
    with open(big, "wb") as f:
        f.truncate(17 << 20)
    with pytest.raises(fabkit.InputError, match="at most 16777216 bytes"):
        flatpack.check_file(big)
    bad = tmp_path / "bad.yaml"
    bad.write_bytes(b"fabkit: flatpack/1\nname: \xff\xfe\n")
    with pytest.raises(fabkit.InputError, match="not UTF-8"):
        flatpack.check_file(bad)
    for loader in (rods.Structure.from_file, hacks.load_design, templates.load):
        with pytest.raises(fabkit.InputError, match="not a regular file"):
            loader("/dev/zero")
    assert time.monotonic() - started < 10  # nothing blocked on the FIFO


def test_saving_never_replaces_a_fifo_or_writes_through_a_link(tmp_path):
    c = flatpack.Component("box")
    c.addSubcomponent("side", "Rectangle", width=100, height=50)
    fifo = tmp_path / "design.yaml"
    os.mkfifo(fifo)
    with pytest.raises(fabkit.WriteError, match="not a regular file"):
        c.toYaml(str(fifo))
    assert fifo.is_fifo()
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "victim.yaml").write_text("keep me")
    inside = tmp_path / "inside"
    inside.mkdir()
    (inside / "design.yaml").symlink_to(outside / "victim.yaml")
    with pytest.raises(fabkit.WriteError, match="points out of its directory"):
        c.toYaml(str(inside / "design.yaml"))
    assert (outside / "victim.yaml").read_text() == "keep me"
    # A plain file is written whole.
    c.toYaml(str(tmp_path / "ok.yaml"))
    assert (tmp_path / "ok.yaml").read_text().startswith("fabkit: flatpack/1")


# ---- time limits ----------------------------------------------------------------------------

@pytest.mark.parametrize("bad", [0, -1, float("nan"), float("inf"), 1e7, "1", True])
def test_time_limits_are_validated(bad):
    with pytest.raises((TypeError, ValueError)):
        flatpack.check_file(EXAMPLES / "flatpack/stool.yaml", time_limit=bad)
    with pytest.raises((TypeError, ValueError)):
        hacks.load_design(EXAMPLES / "hacks/bird_feeder.yaml", time_limit=bad)


def test_time_limits_stop_every_kit_with_the_iterations_done():
    # A limit far below what the work takes: a TimeLimitError that says how far it got.
    started = time.monotonic()
    design = hacks.load_design(EXAMPLES / "hacks/reading_nook.yaml")
    with pytest.raises(fabkit.TimeLimitError, match="stopped at the deadline after") as e:
        design.assembly.solve(time_limit=0.02)
    assert e.value.result is not None
    with pytest.raises(fabkit.TimeLimitError, match="stopped at the deadline after"):
        hacks.load_design(EXAMPLES / "hacks/reading_nook.yaml", time_limit=0.001)
    with pytest.raises(fabkit.TimeLimitError, match="stopped at the deadline"):
        templates.load(EXAMPLES / "templates/bench_with_backrest.yaml", time_limit=1e-6)
    with pytest.raises(fabkit.TimeLimitError, match="stopped at the deadline"):
        flatpack.check_file(EXAMPLES / "flatpack/bunk_bed.yaml", time_limit=1e-6)
    s = rods.Structure.from_file(EXAMPLES / "rods/geodesic_dome.yaml")
    with pytest.raises(fabkit.TimeLimitError, match="stopped at the deadline after"):
        s.build(time_limit=0.05, engrave=False)
    assert time.monotonic() - started < 30
    # Generous limits change nothing: the same verdict and pose either way.
    unlimited = design.assembly.solve()
    limited = design.assembly.solve(time_limit=600)
    assert limited.stable == unlimited.stable
    assert limited.target_error == pytest.approx(unlimited.target_error, abs=1e-9)


def test_every_save_refuses_a_fifo_and_keeps_it(tmp_path):
    # Every kit's writers, from Python: through the same atomic writer as the command line.
    def fifo(name):
        p = tmp_path / name
        os.mkfifo(p)
        return p

    nook = hacks.load_design(EXAMPLES / "hacks/bird_feeder.yaml").assembly.solve()
    s = rods.Structure(nodes=[[0, 0, 0], [300, 0, 0], [0, 300, 0], [0, 0, 300]],
                       edges=[(0, 1), (0, 2), (0, 3), (1, 2), (2, 3), (3, 1)])
    built = s.build(engrave=False)
    out = tmp_path / "rods_out"
    out.mkdir()
    os.mkfifo(out / "report.json")
    model = templates.load(EXAMPLES / "templates/table_with_shelf.yaml")
    tout = tmp_path / "templates_out"
    tout.mkdir()
    os.mkfifo(tout / "bom.csv")
    saves = [
        ("result.json", lambda p: nook.save_json(str(p))),
        ("scene.glb", lambda p: nook.save_glb(str(p))),
        ("joint.stl", lambda p: built._r.save_joint_stl(0, str(p))),
        ("board.stl", lambda p: rods.tolerance_board(str(p))),
        ("catalog.sqlite", lambda p: _fabkit.templates.Catalog.bundled().save_as(str(p))),
    ]
    for name, save in saves:
        p = fifo(name)
        with pytest.raises(fabkit.WriteError, match="not a regular file"):
            save(p)
        assert p.is_fifo(), name
    with pytest.raises(fabkit.WriteError, match="not a regular file"):
        built.save(out)
    assert (out / "report.json").is_fifo()
    with pytest.raises(fabkit.WriteError, match="not a regular file"):
        model.build(tout)
    assert (tout / "bom.csv").is_fifo()
    # And a catalog saved to a plain file opens again.
    _fabkit.templates.Catalog.bundled().save_as(str(tmp_path / "c.sqlite"))
    assert len(_fabkit.templates.Catalog.open(str(tmp_path / "c.sqlite"))) == len(_fabkit.templates.Catalog.bundled())
