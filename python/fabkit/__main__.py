"""python -m fabkit run PROGRAM.py | sweep FAMILY.py  (what `fabkit run` / `fabkit sweep` do)."""

import runpy
import sys


def _sweep(path):
    """A family file defines build(**params) -> Assembly and grid = {name: [values]};
    optionally group = "name" to report the best stable variant per value of that parameter."""
    from .hacks import sweep

    family = runpy.run_path(path, run_name="fabkit_family")
    if "build" not in family or "grid" not in family:
        print(f"error: {path} must define build(**params) and grid", file=sys.stderr)
        return 2
    ranked = sweep(family["build"], family["grid"], threads=family.get("threads"))
    group = family.get("group")
    stable = sum(1 for v in ranked if v.stable)
    print(f"{len(ranked)} variants solved, {stable} stable, {len(ranked.rejected)} rejected")
    keys = family["grid"][group] if group else [None]
    for k in keys:
        best = ranked.best(**({group: k} if group else {}))
        label = f"{group}={k}: " if group else "best: "
        if best is None:
            print(f"{label}no stable variant")
        else:
            pos, rot = best.target_error
            print(f"{label}{best.params}  target off by {pos:.1f} mm, {rot:.1f}°")
    return 0


def main(argv):
    if len(argv) < 2 or argv[0] not in ("run", "sweep"):
        print("usage: python -m fabkit run PROGRAM.py [args] | sweep FAMILY.py", file=sys.stderr)
        return 1
    if argv[0] == "sweep":
        return _sweep(argv[1])
    sys.argv = argv[1:]
    runpy.run_path(argv[1], run_name="__main__")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
