"""Design and fabrication by example (Schulz et al. 2014) on fabkit's C++ engine.

Compose furniture from a database of fabricable templates, reshape it without breaking what
makes it buildable, and get the bill of materials, cut diagrams and a stability verdict::

    from fabkit import templates

    model = templates.Model("table with a bottom shelf")
    model.add("dining_table", as_="table")
    model.add("bookshelf/shelves/bottom_shelf", as_="shelf", at=[0, 0, 40])   # snaps, connects
    model.set("table", "size_z", 760)            # every relation still holds
    print(model.max_violation())                 # ~1e-12 mm
    print(model.bom()["total"])                  # USD
    print(model.stability(loads=[("top", [780, 430, 760], [0, 0, -300])])["stable"])
    model.build("out")                           # bom.csv, report.html, cut diagrams, scene.glb

``templates.Database.bundled().names()`` lists the source designs; every node of each is a
template (``"bookshelf/shelves"``). Errors raise ``fabkit.InputError`` (bad names, values),
``fabkit.InfeasibleError`` (no connection found, a piece larger than any stock) or
``fabkit.WriteError``.
"""

from ._fabkit import templates as _k
from ._fabkit import Error, InfeasibleError, InputError

__all__ = ["Catalog", "Database", "Model", "load", "CONTROLS", "Error", "InputError", "InfeasibleError"]

#: The six controls of a node's bounding box (paper Fig. 7): centre and size along x, y, z (mm).
CONTROLS = ("center_x", "center_y", "center_z", "size_x", "size_y", "size_z")

Catalog = _k.Catalog
Database = _k.Database


class Model:
    """A working model: templates composed, snapped and connected (paper §4)."""

    def __init__(self, name="model", database=None):
        self._m = _k.Model(name, database)

    @classmethod
    def _wrap(cls, m):
        self = cls.__new__(cls)
        self._m = m
        return self

    @property
    def name(self):
        return self._m.name

    @property
    def part_count(self):
        """Parts the model has now (patterns counted part by part)."""
        return self._m.part_count

    def add(self, template, as_="", at=None, snap=True, connect=True):
        """Adds a template ("design" or "design/path/to/node") named ``as_``, dropped with its
        centre at ``at`` (mm). After the first, each is snapped (§4.4) and connected (§4.5);
        returns what happened. Raises InfeasibleError (and leaves the model unchanged) when a
        linked part cannot be joined."""
        return self._m.add(template, as_, at, snap, connect)

    def remove(self, name):
        """Removes a part with its connectors and relations."""
        self._m.remove(name)

    def controls(self, node=""):
        """The six controls of a node (default: the whole model): value (mm) and whether it is
        hidden (fully constrained)."""
        return self._m.controls(node)

    def drag(self, node, control, delta):
        """Paper eq. 2: moves ``control`` of ``node`` by ``delta`` mm; the nearest feasible shape
        when a constraint stops it (``message`` names it)."""
        return self._m.drag(node, control, delta)

    def set(self, node, control, value):
        """Sets ``control`` of ``node`` to ``value`` mm if feasible, else the nearest feasible
        shape with the binding constraint in ``message``."""
        return self._m.set(node, control, value)

    def max_violation(self):
        """The largest violation of any hard relation, mm (0 up to rounding)."""
        return self._m.max_violation()

    def parts(self):
        """Every part: name, item, role, centre and size (mm)."""
        return self._m.parts()

    def box(self, node=""):
        """(centre, size) of a node's bounding box, mm."""
        return self._m.box(node)

    def stability(self, loads=(), friction=0.5):
        """Static equilibrium with friction (§4.6); ``loads`` are (part, [x, y, z] mm,
        [fx, fy, fz] N)."""
        return self._m.stability(list(loads), friction)

    def bom(self):
        """The bill of materials: lines (item, parts, units to buy, total USD, supplier, cut
        sizes), the total and the same as CSV."""
        return self._m.bom()

    def build(self, directory, time_limit=None):
        """Writes bom.csv, bom.json, report.html, cut diagrams, scene.glb, stability.glb,
        model.stl and model.json into ``directory``. Raises TimeLimitError (nothing written)
        when the check takes longer than ``time_limit`` seconds."""
        return self._m.build(str(directory), time_limit)

    def describe(self):
        """The model's template tree, items, visible controls and connections as text."""
        return self._m.describe()


def load(path, database=None, time_limit=None):
    """A model from a ``fabkit: templates/1`` file (composed step by step). Raises
    TimeLimitError when composing takes longer than ``time_limit`` seconds."""
    return Model._wrap(_k.Model.load(str(path), database, time_limit))
