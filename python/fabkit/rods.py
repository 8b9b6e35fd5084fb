"""RodSteward: rod-and-joint structures on fabkit's C++ engine.

A structure is a network of nodes (mm, z up) and edges; fabkit computes a 3D-printable joint
for every node and the exact length of every rod, checks that it can be built and will stand,
plans the cuts from stock dowels and orders the assembly::

    from fabkit.rods import Structure

    s = Structure(nodes=[[0, 0, 0], [300, 0, 0], [0, 300, 0], [0, 0, 300]],
                  edges=[(0, 1), (0, 2), (0, 3), (1, 2), (2, 3), (3, 1)],
                  diameter=6.35, wall=2, socket=15, tolerance=0.15)
    result = s.check()                # findings, rod lengths, balance, cut plan, assembly
    for f in result.findings:
        print(f)
    built = s.build()                 # exact, engraved joints
    built.save("out")                 # joint_01.stl ..., joints.3mf, scene.glb, cut plan, ...

Edges index ``nodes`` from 0; joint IDs (engraved, and in file names) count from 1. Bad input
raises ``fabkit.InputError`` with the reason; a design that cannot be built raises
``fabkit.InfeasibleError`` from ``build()``. Failed checks do not raise: they are findings.
"""

import difflib
import json

from ._fabkit import rods as _k
from ._fabkit import Error, InfeasibleError, InputError, TimeLimitError

__all__ = [
    "Structure", "Result", "Finding", "Joint", "Rod", "Balance", "CutPlan", "AssemblyStep",
    "plan_cuts", "tolerance_board", "rod_materials", "Error", "InputError", "InfeasibleError",
]

_PROFILES = {"circle": 0, "round": 0, "triangle": 3, "square": 4, "hexagon": 6, "octagon": 8}
_PARAMETERS = ["radius", "diameter", "profile", "circle_sides", "wall", "socket", "tolerance",
               "leaf_offset", "min_rod_length", "merge_tolerance", "rod_material", "joint_material",
               "rod_density", "stock_length", "stock_end_padding", "stock_kerf"]


def rod_materials():
    """The rod material presets ("hardwood", "oak", "pine", ...)."""
    return list(_k.rod_materials())


def _parameters(base=None, **kw):
    p = _k.Parameters() if base is None else _copy(base)
    for key, value in kw.items():
        if key not in _PARAMETERS:
            close = difflib.get_close_matches(key, _PARAMETERS, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            raise TypeError(f"unknown parameter '{key}'{hint} (expected one of: {', '.join(_PARAMETERS)})")
        if key == "diameter":
            p.radius = float(value) / 2
        elif key == "profile":
            if isinstance(value, str):
                if value not in _PROFILES:
                    raise InputError(f"profile '{value}' is not one of {', '.join(_PROFILES)} or a number of sides")
                p.sides = _PROFILES[value]
            else:
                p.sides = int(value)
        else:
            setattr(p, key, value)
    p.validate()
    return p


def _copy(p):
    q = _k.Parameters()
    for name in ["radius", "sides", "circle_sides", "wall", "socket", "tolerance", "leaf_offset",
                 "min_rod_length", "merge_tolerance", "stock_length", "stock_end_padding", "stock_kerf"]:
        setattr(q, name, getattr(p, name))
    q.rod_material = p.rod_material if p.rod_material != "custom" else "hardwood"
    if p.rod_material == "custom":
        q.rod_density = p.rod_density
    q.joint_material = p.joint_material if p.joint_material != "custom" else "pla"
    return q


class Finding:
    """One named finding: ``severity`` ("error", "warning", "note"), ``code``
    ("rods-intersect", ...), ``kind`` (its class: "check", "infeasible", ...), ``message``."""

    def __init__(self, d):
        self.severity = d["severity"]
        self.code = d["code"]
        self.kind = d["class"]
        self.message = d["message"]
        self.line = d.get("line")
        self.text = d["text"]

    def __str__(self):
        return self.text

    def __repr__(self):
        return f"Finding({self.severity}, {self.code}: {self.message})"


class Joint:
    """A joint: ``id``, ``label`` (the engraved text), ``position`` (mm), ``rods``; after
    ``build()`` also ``volume`` (mm³), ``mass_g``, ``watertight``, ``engraving`` and ``file``."""

    def __init__(self, d, result, index):
        self.index = index
        self.id = d["id"]
        self.label = d["label"]
        self.position = d["position_mm"]
        self.rods = d["rods"]
        self.volume = d.get("volume_mm3")
        self.mass_g = d.get("mass_g")
        self.watertight = d.get("watertight")
        self.engraving = d.get("engraving")
        self.file = d.get("file")
        self.same_as_printed = d.get("same_as_printed")
        self._result = result

    def mesh(self):
        """(vertices, faces) of the built joint in its local frame (node at the origin, mm)."""
        return self._result._r.joint_mesh(self.index)

    def save_stl(self, path):
        """Writes the joint as a binary STL in its print pose."""
        self._result._r.save_joint_stl(self.index, str(path))

    def __repr__(self):
        return f"Joint({self.label}, {len(self.rods)} rods)"


class Rod:
    """A rod: ``name`` ("rod 03-07"), ``joints`` (IDs), ``length`` (mm, as cut),
    ``edge_length``, ``offsets`` (g at each end), ``angles`` (smallest angle at each end, °),
    ``utilisation`` (structural, when analysed)."""

    def __init__(self, d):
        self.name = d["name"]
        self.joints = tuple(d["joints"])
        self.length = d["length_mm"]
        self.edge_length = d["edge_length_mm"]
        self.offsets = tuple(d["offsets_mm"])
        self.angles = tuple(d["smallest_angles_deg"])
        self.utilisation = d.get("utilisation")
        self.red = d["red"]

    def __repr__(self):
        return f"Rod({self.name}, {self.length:.2f} mm)"


class Balance:
    """``stands``, ``margin`` (mm inside the support polygon; negative: outside), ``mass``
    (kg), ``center_of_mass`` (mm), ``ground_joints`` (IDs), ``support_polygon`` (mm)."""

    def __init__(self, d):
        self.stands = d["stands"]
        self.margin = d["margin_mm"]
        self.mass = d["mass_kg"]
        self.center_of_mass = d["center_of_mass_mm"]
        self.ground_joints = d["ground_joints"]
        self.support_polygon = d["support_polygon_mm"]


class CutPlan:
    """``stock_count`` stock rods to buy, ``lower_bound``, ``proven_optimal``, ``summary``, and
    ``stock``: per stock rod a list of (rod name, start mm, length mm)."""

    def __init__(self, d):
        self.stock_count = d["stock_count"]
        self.lower_bound = d["lower_bound"]
        self.proven_optimal = d["proven_optimal"]
        self.summary = d["summary"]
        if "pieces" in (d["stock"][0] if d["stock"] and isinstance(d["stock"][0], dict) else {}):
            self.stock = [[(p["rod"], p["start_mm"], p["length_mm"]) for p in s["pieces"]] for s in d["stock"]]
        else:
            self.stock = [[tuple(p) for p in s] for s in d["stock"]]
        self.svg = d.get("svg")
        self.csv = d.get("csv")


class AssemblyStep:
    """``kind`` ("joint" or "rod"), ``text``; joints: ``joint``/``label``; rods: ``rod``,
    ``length`` (mm), ``into`` and ``towards`` (joint IDs)."""

    def __init__(self, d):
        self.kind = d["kind"]
        self.text = d["text"]
        self.joint = d.get("joint")
        self.label = d.get("label")
        self.rod = d.get("rod")
        self.length = d.get("length_mm")
        self.into = d.get("into")
        self.towards = d.get("towards")

    def __repr__(self):
        return f"AssemblyStep({self.text})"


class Result:
    """What ``check()`` or ``build()`` found and made: ``termination`` ("built",
    "built-with-findings", ...), ``message``, ``passed``, ``findings``, ``errors``, ``rods``,
    ``joints``, ``cut_plan``, ``balance``, ``structure`` (frame analysis), ``assembly``,
    ``report`` (the report.json dict) and ``save(directory)``."""

    def __init__(self, r):
        self._r = r
        self.report = json.loads(r.report_json())
        self.termination = r.termination
        self.message = r.message
        self.findings = [Finding(f) for f in self.report["findings"]]
        self.errors = [f for f in self.findings if f.severity == "error"]
        self.passed = not self.errors
        self.rods = [Rod(d) for d in self.report["rods"]]
        self.joints = [Joint(d, self, i) for i, d in enumerate(self.report["joints"])]
        self.cut_plan = CutPlan(self.report["cut_plan"]) if "cut_plan" in self.report else None
        self.balance = Balance(self.report["balance"])
        self.structure = self.report["structure"]
        self.assembly = [AssemblyStep(s) for s in json.loads(r.assembly_json())["steps"]]
        self.timings_ms = self.report["timings_ms"]

    @property
    def rod_lengths(self):
        """{rod name: length as cut (mm)}."""
        return {r.name: r.length for r in self.rods}

    def save(self, directory):
        """Writes every output (as ``fabkit build -o``); returns the paths written."""
        return [str(p) for p in self._r.save(str(directory))]

    def __repr__(self):
        return f"Result({self.termination}: {self.message})"


class Structure:
    """A rod structure: ``nodes`` (mm), ``edges`` (0-based pairs) and parameters (keywords:
    radius or diameter, profile, wall, socket, tolerance, rod_material, joint_material,
    stock_length, stock_end_padding, stock_kerf, min_rod_length, ...)."""

    def __init__(self, nodes=None, edges=None, name="", _design=None, **parameters):
        if _design is not None:
            self._d = _design
            return
        if nodes is None or edges is None:
            raise TypeError("Structure(nodes, edges, ...) needs both node positions and edges")
        self._d = _k.Design.from_lists(list(nodes), list(edges), _parameters(**parameters), name)

    @classmethod
    def from_file(cls, path):
        """Reads a ``fabkit: rods/1`` design file."""
        return cls(_design=_k.Design.from_file(str(path)))

    @classmethod
    def from_text(cls, yaml, name="design.yaml"):
        return cls(_design=_k.Design.from_text(yaml, name))

    @property
    def name(self):
        return self._d.name

    @property
    def nodes(self):
        return self._d.nodes

    @property
    def edges(self):
        return self._d.edges

    @property
    def parameters(self):
        return self._d.parameters

    def with_parameters(self, **parameters):
        """The same network with some parameters changed."""
        return Structure(_design=self._d.with_parameters(_parameters(self._d.parameters, **parameters)))

    def scaled(self, factor):
        """The same structure with every node position multiplied by ``factor``: the joints
        stay the same (RodSteward §6), only the rods change."""
        return Structure(_design=self._d.scaled(float(factor)))

    def add_load(self, node, force):
        """A force (N, [fx, fy, fz]) at node index ``node``; it counts in the frame analysis
        and, pointing down, as weight for balance."""
        self._d.add_load(int(node), force)

    def preview(self):
        """What the designer draws (no booleans): {"joints": [(vertices, faces)], "rods": ...,
        "rod_lengths": [...], "offsets": [(g_a, g_b)]}."""
        return _k.preview(self._d)

    def check(self, seed=1, time_limit=None):
        """Offsets, rod lengths, every check, the frame analysis, the cut plan and the assembly
        order (no joints are built). Failed checks are findings, not exceptions."""
        return Result(_k.check(self._d, seed, time_limit))

    def build(self, seed=1, time_limit=None, threads=2, engrave=True):
        """check() plus the exact, engraved joints. Raises InfeasibleError when rods cannot be
        made (no length left, longer than the stock) and TimeLimitError at the time limit."""
        r = Result(_k.build(self._d, seed, time_limit, threads, engrave))
        messages = "\n".join(f.text for f in r.errors)
        if r.termination == "infeasible":
            raise InfeasibleError(messages)
        if r.termination == "time-limit":
            raise TimeLimitError(messages)
        if r.termination == "failed":
            raise Error(messages)
        return r

    def reused_joints(self, printed):
        """[(node, printed node)] for every joint of this structure that is the same as one of
        ``printed`` (a Structure whose joints are already printed)."""
        return _k.matching_joints(printed._d, self._d)

    def __repr__(self):
        return f"Structure({self.name or 'unnamed'}: {len(self.nodes)} joints, {len(self.edges)} rods)"


def plan_cuts(lengths, stock_length, end_padding=10.0, kerf=0.0, time_limit=0.8, seed=1):
    """Packs pieces (lengths in mm, or (label, length) pairs) into stock of ``stock_length``
    mm with ``end_padding`` at each end and ``kerf`` per cut. Returns a CutPlan (with ``svg``
    and ``csv`` text); a piece longer than the stock raises InfeasibleError."""
    pieces = []
    for i, item in enumerate(lengths):
        if isinstance(item, (tuple, list)):
            pieces.append((str(item[0]), float(item[1])))
        else:
            pieces.append((f"piece {i + 1}", float(item)))
    return CutPlan(_k.plan_cuts(pieces, float(stock_length), float(end_padding), float(kerf),
                                float(time_limit), int(seed)))


def tolerance_board(path, tolerance_from=-0.1, tolerance_to=0.3, step=0.05, **parameters):
    """Writes a printable STL plate of sockets for the rod (keywords as Structure's), one per
    tolerance from ``tolerance_from`` to ``tolerance_to`` mm, each labelled. Returns the
    tolerances."""
    return _k.tolerance_board(_parameters(**parameters), float(tolerance_from), float(tolerance_to),
                              float(step), str(path))
