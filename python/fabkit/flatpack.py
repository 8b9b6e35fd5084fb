"""Flat-pack furniture from planar pieces (Yan, Zhao and Mehta), on fabkit's C++ engine.

The paper's Fig. 3 program runs with only its imports changed::

    from fabkit.flatpack import Component
    from fabkit.flatpack import FingerJoint

    Component = Component()
    Component.addSubcomponent("A", "Rectangle")
    Component.addSubcomponent("B", "Rectangle")
    Component.addParameter("l1", 30, paramtype="length")
    Component.addParameter("l2", 60, paramtype="length")
    Component.addConstraint(("A", "l"), "l1")
    ...
    Component.addEdgeToEdge(("A", "t"), ("B", "b"), orientation="front-front",
                            offset=(0, 0, 0), angle=(90, 0, 0))
    Component.toYaml("library/ConnectionJointBuilder.yaml")
    Component.makeOutput("output/ConnectionJointBuilder", thickness=3,
                         joint=FingerJoint(thickness=3))

Every camelCase method has a snake_case twin (add_subcomponent, ...). Problems raise
``fabkit.InputError`` (bad names, under- or over-constrained designs) or another
``fabkit.Error`` with the file-style message the command line prints.
"""

import json
import os

from . import _fabkit
from ._fabkit import flatpack as _k

__all__ = ["Component", "FingerJoint", "check_file", "build_file"]


class FingerJoint:
    """The paper's joint specification: board thickness, kerf Δ (per side) and interference δ, mm."""

    def __init__(self, thickness=3, kerf=0.1, interference=0.1):
        self.thickness = float(thickness)
        self.kerf = float(kerf)
        self.interference = float(interference)


def _expr(value):
    if isinstance(value, bool):
        raise TypeError("expressions are numbers or text like '2*l2 + 10'")
    if isinstance(value, (int, float)):
        return repr(float(value))
    if isinstance(value, str):
        return value
    raise TypeError(f"expected a number or an expression, not {type(value).__name__}")


def _quantity(q):
    if isinstance(q, (tuple, list)) and len(q) == 2:
        return f"{q[0]}.{q[1]}"
    if isinstance(q, str):
        return q
    raise TypeError('a quantity is ("A", "l") or "A.l"')


class Component:
    """A design under construction: subcomponents, parameters, constraints and connections.

    It is itself usable as a component of a larger design once saved with toYaml (paper §4.2).
    """

    def __init__(self, name="design"):
        self.name = name
        self._parameters = {}
        self._components = []
        self._constraints = []
        self._connections = []
        self._interfaces = {}
        self._uses = {}
        self._material = {"name": "plywood", "thickness": 3, "kerf": 0.1, "interference": 0.1}
        self._sheet = None

    # -- the paper's API ----------------------------------------------------------------------
    def addSubcomponent(self, name, component_type, **params):
        """Adds a component of a built-in type ("Rectangle", ...) or of a saved design file
        (a path ending in .yaml); keyword arguments set its parameters."""
        entry = {"name": name}
        if str(component_type).endswith((".yaml", ".yml")):
            type_name = os.path.splitext(os.path.basename(component_type))[0]
            self._uses[type_name] = os.path.abspath(component_type)
            entry["type"] = type_name
        else:
            entry["type"] = component_type
        for k, v in params.items():
            entry[k] = _expr(v)
        self._components.append(entry)
        return self

    def addParameter(self, name, value=None, paramtype="length", meta=False, description=""):
        """A design parameter with a default value; paramtype is length, angle, count or number."""
        p = {"type": paramtype}
        if value is not None:
            p["value"] = float(value)
        if meta:
            p["meta"] = True
        if description:
            p["description"] = description
        self._parameters[name] = p
        return self

    def addConstraint(self, quantity, expression):
        """Binds a dimension to an expression: addConstraint(("A", "w"), "2*l2 + 10")."""
        self._constraints.append(f"{_quantity(quantity)} = {_expr(expression)}")
        return self

    def addEdgeToEdge(self, a, b, orientation="front-front", offset=(0, 0, 0), angle=(0, 0, 0), alignment=None, name=None):
        """The paper's 5-tuple connection: A's edge on B's edge, front-front or front-back, then
        an offset (mm, in B's edge frame) and a rotation (degrees about A's own edge axes).
        `alignment` is accepted as a synonym of `orientation` when it names one."""
        if alignment in ("front-front", "front-back"):
            orientation = alignment
        if len(offset) != 3 or len(angle) != 3:
            raise ValueError("offset and angle are (x, y, z)")
        c = {"connect": [f"{a[0]}.{a[1]}", f"{b[0]}.{b[1]}"], "alignment": orientation,
             "offset": [_expr(v) for v in offset], "rotation": [_expr(v) for v in angle]}
        if name:
            c["name"] = name
        self._connections.append(c)
        return self

    def addInterface(self, name, component_edge):
        """Exports an edge ("A.t" or ("A", "t")) for use when this design is a component."""
        self._interfaces[name] = _quantity(component_edge)
        return self

    def setMaterial(self, thickness=3, kerf=0.1, interference=0.1, name="plywood"):
        self._material = {"name": name, "thickness": float(thickness), "kerf": float(kerf),
                          "interference": float(interference)}
        return self

    def setSheet(self, width=600, height=400, spacing=3, margin=5):
        self._sheet = {"width": width, "height": height, "spacing": spacing, "margin": margin}
        return self

    def design_text(self):
        """The design as flatpack/1 design-file text (JSON, which YAML reads)."""
        d = {"fabkit": "flatpack/1", "name": self.name, "material": self._material,
             "components": self._components}
        if self._parameters:
            d["parameters"] = self._parameters
        if self._constraints:
            d["constraints"] = self._constraints
        if self._connections:
            d["connections"] = self._connections
        if self._interfaces:
            d["interfaces"] = self._interfaces
        if self._uses:
            d["uses"] = self._uses
        if self._sheet:
            d["sheet"] = self._sheet
        return json.dumps(d, indent=1)

    def check(self, time_limit=None):
        """Places, detects and cuts; returns the report (dict: counts, pieces, joints, ...).
        Raises TimeLimitError past ``time_limit`` seconds."""
        return _k.check(self.design_text(), f"{self.name}.yaml", os.getcwd(), time_limit)

    def toYaml(self, path):
        """Saves the design as a flatpack/1 design file (usable with `uses:` and fabkit build)."""
        text = _k.to_yaml(self.design_text(), f"{self.name}.yaml")
        directory = os.path.dirname(path)
        if directory:
            os.makedirs(directory, exist_ok=True)
        _fabkit.write_text_file(str(path), text)  # atomically; never through a FIFO or link
        return path

    def makeOutput(self, path, tree=False, display=False, thickness=None, joint=None, time_limit=None):
        """Writes the cut sheets (SVG, DXF), model.stl, scene.glb and report.json into `path`.
        `thickness` and `joint` set the material (paper Fig. 3); tree and display are accepted
        for the paper's programs and do nothing."""
        if joint is not None:
            self.setMaterial(joint.thickness, joint.kerf, joint.interference, self._material["name"])
        if thickness is not None:
            self._material["thickness"] = float(thickness)
        os.makedirs(path, exist_ok=True)
        return _k.build(self.design_text(), f"{self.name}.yaml", os.getcwd(), os.path.abspath(path),
                        time_limit)

    # -- snake_case twins ---------------------------------------------------------------------
    add_subcomponent = addSubcomponent
    add_parameter = addParameter
    add_constraint = addConstraint
    add_edge_to_edge = addEdgeToEdge
    add_interface = addInterface
    set_material = setMaterial
    set_sheet = setSheet
    to_yaml = toYaml
    make_output = makeOutput


def _read_design(path):
    # A regular file of at most 16 MiB (not a FIFO or /dev/zero), as the command line reads it.
    return _fabkit.read_text_file(str(path), "design file")


def check_file(path, time_limit=None):
    """Checks a design file; returns the report dict. Raises TimeLimitError past
    ``time_limit`` seconds."""
    return _k.check(_read_design(path), str(path), os.path.dirname(os.path.abspath(path)), time_limit)


def build_file(path, output_dir, time_limit=None):
    """Builds a design file's outputs into output_dir; returns the report dict. Raises
    TimeLimitError past ``time_limit`` seconds (nothing is written then)."""
    return _k.build(_read_design(path), str(path), os.path.dirname(os.path.abspath(path)),
                    os.path.abspath(output_dir), time_limit)
