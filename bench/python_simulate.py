"""geartopo.simulate from Python against the C++ call it wraps (docs/performance.md, "Python"): the default scene,
every tooth, its 7×9 grid and 100/150-point traces, on one thread — geartopo_bench's
Simulate/<method>/grid7x9+traces100x150/threads:1/process_time/real_time. Prints per method the median wall and process CPU
time of N calls, ms. Usage: PYTHONPATH=build/python python3 bench/python_simulate.py [N] [THREADS]"""
import statistics
import sys
import time
from pathlib import Path

import geartopo

n = int(sys.argv[1]) if len(sys.argv) > 1 else 100
threads = int(sys.argv[2]) if len(sys.argv) > 2 else 1
scene = geartopo.load_scene(Path(__file__).resolve().parents[1] / "scenes" / "skmc1200w-mn14-z35.yaml")
for method in ("exact", "linear"):
    geartopo.simulate(scene, teeth="all", method=method, threads=threads)  # warm-up
    wall, cpu = [], []
    for _ in range(n):
        w, c = time.perf_counter(), time.process_time()
        geartopo.simulate(scene, teeth="all", method=method, threads=threads)
        cpu.append(1e3 * (time.process_time() - c))
        wall.append(1e3 * (time.perf_counter() - w))
    print(f"geartopo.simulate {method:<6} all teeth, 7x9 + traces 100x150, threads {threads}: "
          f"wall {statistics.median(wall):.3f} ms, CPU {statistics.median(cpu):.3f} ms (medians of {n} calls)")
