"""Design families: evaluate many program variants in parallel (paper §4.4, Fig. 11)."""

import itertools
import os

from ._fabkit import Error
from ._fabkit import hacks as _k


class Variant:
    """One solved member of a family: its parameters and its result."""

    def __init__(self, params, result):
        self.params = params
        self.result = result

    @property
    def stable(self):
        return self.result.stable

    @property
    def target_error(self):
        return self.result.target_error

    @property
    def design_error(self):
        """What the design can still be judged by: position (mm) plus tilt (degrees) plus the
        twist about the vertical unless the assembly turns the target there at no cost."""
        e = self.result.target_pose_error
        return e["position_mm"] + e["tilt_deg"] + (0.0 if e["twist_free"] else abs(e["twist_deg"]))

    def __repr__(self):
        pos, rot = self.result.target_error
        verdict = "stable" if self.stable else "falls apart"
        return f"<{self.params}: {verdict}, target off by {pos:.1f} mm, {rot:.1f}°>"


def sweep(build, grid, threads=None, progress=True, remedies=False):
    """Builds ``build(**params)`` for every combination of ``grid`` (a dict from parameter
    name to a list of values), solves them all on C++ threads, and returns the variants
    ranked: stable ones first, then by design error (position mm + tilt degrees + twist
    degrees, the twist left out where the target turns freely about the vertical).

    A variant whose program raises fabkit.Error (a connect that cannot be made) is left out
    and reported in the returned list's ``rejected`` attribute.

    With ``remedies=True`` a variant that does not hold is also solved with connects turned the
    other way, and its ``result.remedy`` names one that holds, as ``solve()`` does; the sweep
    leaves it out by default (it is most of the time a variant that does not hold takes, and
    the ranking does not read it)."""
    if not callable(build):
        raise TypeError("sweep() takes a function build(**params) that returns an Assembly")
    if not isinstance(grid, dict) or not grid:
        raise TypeError("sweep() takes a grid: a dict from parameter name to a list of values")
    names = list(grid)
    combos = [dict(zip(names, values)) for values in itertools.product(*(grid[n] for n in names))]
    built, params, rejected = [], [], []
    for p in combos:
        try:
            a = build(**p)
        except Error as e:
            rejected.append((p, str(e)))
            continue
        if a is None or not hasattr(a, "_assembly"):
            raise TypeError("build(**params) must return an Assembly")
        built.append(a._assembly)
        params.append(p)
    results = _k.solve_many(built, threads or os.cpu_count() or 1, progress, remedies)
    variants = [Variant(p, r) for p, r in zip(params, results)]
    variants.sort(key=lambda v: (not v.stable, v.design_error))
    ranked = _Ranked(variants)
    ranked.rejected = rejected
    return ranked


class _Ranked(list):
    rejected = []

    def best(self, **fixed):
        """The best stable variant whose parameters match ``fixed`` (or None)."""
        for v in self:
            if v.stable and all(v.params.get(k) == x for k, x in fixed.items()):
                return v
        return None
