#!/usr/bin/env python3
"""A law given as a Python function (geartopo.custom_effect) against the same law compiled as a C++ plug-in, per
simulated point (issue 40: the Python one may cost at most 5×). Google Benchmark cannot host the interpreter, so this
script times both the same way: simulate (exact, the default scene's 7 × 9 grid + 2-point traces, every tooth, all
hardware threads) — the plug-in and the scene expression by geartopo_bench's BM_CustomLaw (run from here, in turns
with the Python cases), the Python law by geartopo.simulate on the same scene and grid.
  cold: a scene made afresh before each run, so each stroke's grid is evaluated (one call per stroke) inside the time;
  warm: the same scene again (the grids kept while the values stay).
The workpiece-warming law of bench_custom_effect.cpp. Median of `--rounds` rounds (default 3).
Run: PYTHONPATH=build/python python3 bench/python_custom_law.py [--bench build/bin/geartopo_bench]"""
import argparse
import json
import statistics
import subprocess
import time
from pathlib import Path

import numpy as np

import geartopo

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "skmc1200w-mn14-z35.yaml"


def warming(params, state):
    return -params["shrink_um_per_mm"] * (state["x_mm"] * state["nx"] + state["y_mm"] * state["ny"]) * (
        1.0 - np.exp(-state["t_s"] / params["tau_s"]))


def cpp_ms(bench):
    """BM_CustomLaw's real time per run (ms): 0 no effect, 1 compiled plug-in, 2 scene expression."""
    out = subprocess.run([bench, "--benchmark_filter=BM_CustomLaw", "--benchmark_format=json",
                          "--benchmark_min_time=1"], capture_output=True, text=True, check=True).stdout
    return {b["name"].split("/")[1]: b["real_time"] for b in json.loads(out)["benchmarks"]}


def python_ms(scene, make_scene, runs=3):
    times = []
    for _ in range(runs):
        s = make_scene() if make_scene else scene
        t0 = time.perf_counter()
        geartopo.simulate(s, teeth="all", method="exact")
        times.append(1e3 * (time.perf_counter() - t0))
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bench", default=str(ROOT / "build" / "bin" / "geartopo_bench"))
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    text = SCENE.read_text().replace("profile_points: 100", "profile_points: 2").replace("helix_points: 150",
                                                                                          "helix_points: 2")
    plain = geartopo.scene_from_yaml(text, source=str(SCENE))
    effect = geartopo.custom_effect("bench_python_warming", {
        "shrink_um_per_mm": {"value": 0.04, "min": -0.1, "max": 0.1, "unit": "um_per_mm"},
        "tau_s": {"value": 200, "min": 30, "max": 20000, "unit": "s"}}, warming)
    warm = plain.with_effect(effect)
    rows = {k: [] for k in ("cpp none", "cpp plug-in", "cpp expression", "py none", "py cold", "py warm")}
    for _ in range(args.rounds):
        c = cpp_ms(args.bench)
        rows["cpp none"].append(c["0"]), rows["cpp plug-in"].append(c["1"]), rows["cpp expression"].append(c["2"])
        rows["py none"].append(python_ms(plain, None))
        rows["py cold"].append(python_ms(None, lambda: plain.with_effect(effect)))
        rows["py warm"].append(python_ms(warm, None))
    med = {k: statistics.median(v) for k, v in rows.items()}
    for k, v in med.items():
        print(f"{k:15s} {v:8.1f} ms")
    print(f"Python law / compiled plug-in: cold {med['py cold'] / med['cpp plug-in']:.2f}×, "
          f"warm {med['py warm'] / med['cpp plug-in']:.2f}× (the module's own overhead: no effect "
          f"{med['py none'] / med['cpp none']:.2f}× the C++ bench's)")


if __name__ == "__main__":
    main()
