"""Wall time of the Fig. 11 design-family sweep (issue 4 target: 80 variants under 2 s on two
cores). Run: PYTHONPATH=build/python /usr/bin/python3 bench/sweep_bench.py"""

import os
import runpy
import statistics
import time

from fabkit.hacks import sweep

here = os.path.dirname(os.path.abspath(__file__))
family = runpy.run_path(os.path.join(here, "..", "examples", "python", "clip_light_family.py"), run_name="family")
build, grid = family["build"], family["grid"]


def timed(g, repetitions=5):
    times = []
    for _ in range(repetitions):
        start = time.perf_counter()
        ranked = sweep(build, g, threads=os.cpu_count(), progress=False)
        times.append(time.perf_counter() - start)
    return statistics.median(times), len(ranked)


for ring in grid["ring"]:
    t, n = timed(dict(grid, ring=[ring]))
    print(f"ring {ring:2}: {n} variants, median {t * 1000:.0f} ms wall")
t, n = timed(grid)
print(f"all rings: {n} variants, median {t * 1000:.0f} ms wall")
