"""Reshape the table with a bottom shelf: longer, narrower, taller — every constraint holds.

    build/bin/fabkit run examples/templates/reshape_table.py [OUT_DIR]
"""

import pathlib
import sys

from fabkit import templates

here = pathlib.Path(__file__).parent
model = templates.load(here / "table_with_shelf.yaml")

for node, control, value in [
    ("table/base/legs", "size_x", 1500),   # the legs move apart; aprons, top and shelf follow
    ("table/base/legs", "size_y", 700),
    ("top", "size_x", 1700),
    ("table", "size_z", 740),
]:
    r = model.set(node, control, value)
    status = "ok" if r["reached"] else "stopped: " + r["message"]
    print(f"{node} {control} -> {r['achieved']:.1f} mm ({status}); "
          f"largest violation {model.max_violation():.1e} mm")
    assert model.max_violation() < 1e-9

bom = model.bom()
print(f"{model.part_count} parts, materials ${bom['total']:.2f}")
print("stable" if model.stability()["stable"] else "UNSTABLE")
if len(sys.argv) > 1:
    print(model.build(sys.argv[1])["message"])
