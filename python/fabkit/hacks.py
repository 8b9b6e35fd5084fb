"""FabHaL, the FabHacks language, on fabkit's C++ engine.

The paper's programs run as written::

    from fabkit.hacks import *

    assembly = Assembly()
    ENV_start = Environment({"part": TowelRackRods()})
    assembly.add(ENV_start, Frame([0, 0, 200], [0, 0, -90]))
    eyehook1 = HookEyeConnector()
    assembly.connect(eyehook1.hole, ENV_start.rod1, alignment="flip")
    ...
    result = assembly.solve()

Every ``connect`` is verified as it is made; a connection that cannot be made raises
``fabkit.ConnectError`` with the reason (parts, primitives, numbers).
"""

from ._fabkit import hacks as _k
from ._fabkit import ConnectError, Error, Frame, TimeLimitError
from ._sweep import sweep

__all__ = [
    "Assembly", "Frame", "Environment", "Error", "ConnectError", "sweep", "load_parts",
    "load_design",
    "Rod", "Hook", "Ring", "Hole", "Tube", "Clip", "Edge", "Surface", "Hemisphere",
]


class Assembly:
    """A fixture hack: an environment, parts, and which primitives connect (paper §4.2)."""

    _seed = 1  # also for assemblies a design file made (Design)

    def __init__(self, seed=1):
        """``seed`` seeds every random start of the closure search and of the solve (same
        program, same seed: same answer)."""
        if isinstance(seed, bool) or not isinstance(seed, int):
            raise TypeError(f"seed must be a whole number, not {type(seed).__name__}")
        if not 0 <= seed < 2**64:
            raise ValueError(f"seed must be from 0 to 2**64 - 1, not {seed}")
        self._seed = seed
        self._assembly = _k.Assembly()

    def add(self, environment, frame=None):
        """Fixes an environment (a part, or one of its primitives) at ``frame``."""
        self._assembly.add(environment, frame)

    def connect(self, a, b, alignment="default", is_fixed=False, time_limit=None):
        """Connects two primitives (in any order). Raises ConnectError if they cannot be
        connected, TimeLimitError if verifying a cycle takes longer than ``time_limit``
        seconds; returns True if the connection closes a cycle. A cycle the closure search
        misses in the program's order of connects is tried again with the connects so far in
        their canonical order (as design files are), so which end is built first does not
        decide whether it closes."""
        if not isinstance(alignment, str):
            raise TypeError('alignment must be "default" or "flip"')
        if not isinstance(is_fixed, bool):
            raise TypeError("is_fixed must be True or False")
        return self._assembly.connect(a, b, alignment, is_fixed, time_limit, self._seed)

    def end_with(self, target, frame=None):
        """The target: a part (its first primitive) or a primitive should end at ``frame``."""
        self._assembly.end_with(target, frame)

    def solve(self, time_limit=None):
        """Reaches the target, relaxes under gravity, and says whether the design holds.

        Returns a result with ``stable``, ``target_error`` (mm, degrees), ``frames`` (part name
        to Frame), ``slipping``, ``timings_ms``, ``summary()``, ``save_json(path)``,
        ``save_glb(path)`` and ``save_all(directory)``. Past ``time_limit`` seconds raises
        TimeLimitError; its ``result`` is the best result so far."""
        r = self._assembly.solve(time_limit, self._seed)
        if r.termination == "TIMEOUT":
            e = TimeLimitError(r.stopped_message)
            e.result = r
            raise e
        return r

    @property
    def part_count(self):
        return self._assembly.part_count


def Environment(entries):
    """The paper's Environment({...}): wraps one part, or makes a part of loose primitives
    whose names are the keys (``Environment({"door": Rod({...})}).door``)."""
    if not isinstance(entries, dict) or not entries:
        raise TypeError('Environment() takes a dict such as {"part": TowelRackRods()}')
    values = list(entries.values())
    if len(values) == 1 and isinstance(values[0], _k.Part):
        return values[0]
    if all(isinstance(v, _k.Primitive) for v in values):
        for k in entries:
            if not isinstance(k, str):
                raise TypeError("Environment() keys name the primitives: use strings")
        return _k.environment_from_primitives(list(entries.items()))
    raise TypeError("Environment() takes either one part or primitives (Rod({...}), Surface({...}), ...)")


def _primitive_constructor(kind):
    def make(params=None):
        return _k.make_primitive(kind, params)

    make.__name__ = kind.capitalize()
    make.__doc__ = f"A {kind} primitive; sizes in mm, e.g. {kind.capitalize()}({{...}})."
    return make


Rod = _primitive_constructor("rod")
Hook = _primitive_constructor("hook")
Ring = _primitive_constructor("ring")
Hole = Ring
Tube = _primitive_constructor("tube")
Clip = _primitive_constructor("clip")
Edge = _primitive_constructor("edge")
Surface = _primitive_constructor("surface")
Hemisphere = _primitive_constructor("hemisphere")


def _part_constructor(name):
    def make(params=None):
        return _k.make_part(name, params)

    make.__name__ = name
    make.__doc__ = f"A {name} from the parts library (fabkit parts {name})."
    return make


def load_parts(path):
    """Adds the parts of a YAML part file (docs/parts.md) to the library: afterwards they are
    constructors here like the built-in ones (``load_parts("bracket.yaml"); WallBracket()``).
    Returns their names."""
    names = _k.load_parts(str(path))
    for name in names:
        globals()[name] = _part_constructor(name)
    return names


class Design:
    """A design file read and verified: ``design.assembly`` (solve it), ``design.parts`` (by the
    names in the file), ``design.name``. Raises fabkit.InputError / InfeasibleError."""

    def __init__(self, path, time_limit=None):
        assembly, self.parts, self.name = _k.load_design(str(path), time_limit)
        self.assembly = Assembly.__new__(Assembly)
        self.assembly._assembly = assembly


def load_design(path, time_limit=None):
    """Reads a hacks design file (``fabkit: hacks/1``, docs/design-format.md); raises
    TimeLimitError when verifying it takes longer than ``time_limit`` seconds."""
    return Design(path, time_limit)


# Every part of the library under its paper/reference name (and aliases such as
# HookEyeLeft5 and TowelRackRods), as constructors: DoubleHook(), ParamTurnbuckle({...}).
for _name in _k.part_names():
    globals()[_name] = _part_constructor(_name)
    __all__.append(_name)
del _name
