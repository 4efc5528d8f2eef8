"""The tutorial's story from Python (docs/tutorial.md §1, 3-5): predict, compare with the demo measurement, diagnose,
add the effect and watch the residual fall. Usage: PYTHONPATH=build/python python3 examples/python/tutorial.py [PNG]"""
import sys
from pathlib import Path

import matplotlib
matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import geartopo

root = Path(__file__).resolve().parents[2]
png = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("residual_before_after.png")

scene = geartopo.load_scene(root / "scenes/skmc1200w-mn14-z35.yaml")
topo = geartopo.simulate(scene, teeth=[1, 18])                      # the model's topology, µm
print(f"simulated {len(topo['deviation_um'])} grid points, {topo['deviation_um'].min():.2f} … {topo['deviation_um'].max():.2f} µm")
measured = scene.measured                                           # the scene's demo CMM measurement (a path from here)
before = geartopo.compare(scene, measured)
diagnosis = geartopo.diagnose(scene, measured)
print(diagnosis["verdict"])
fixed = geartopo.scene_from_yaml(diagnosis["scene_with_effect_yaml"], source=scene.source)  # the scene with the effect
after = geartopo.compare(fixed, measured)
print(f"residual RMS {before['overall']['rms_um']:.2f} µm → {after['overall']['rms_um']:.2f} µm")

b = scene.gear["b_mm"]                                               # face width: the flanks side by side
fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
for ax, result, title in ((axes[0], before, "model as given"), (axes[1], after, "with the diagnosed effect")):
    r = result["residuals"]
    flank = 2 * (r["tooth"] != r["tooth"][0]) + (r["flank"] == "right")  # 0..3: tooth 1 left, right, tooth 18 …
    points = ax.scatter(r["z_mm"] + 1.2 * b * flank, r["diameter_mm"], c=r["residual_um"], cmap="coolwarm",
                        vmin=-4, vmax=4, s=40)
    ax.set_title(f"{title}: RMS {result['overall']['rms_um']:.2f} µm")
    ax.set_xticks([1.2 * b * k + b / 2 for k in range(4)], ["1 left", "1 right", "18 left", "18 right"])
    ax.set_xlabel("tooth, flank (z across the face width)")
axes[0].set_ylabel("diameter (mm)")
fig.colorbar(points, ax=axes, label="residual = measured − model (µm)")
fig.savefig(png, dpi=100)
print(f"wrote {png}")
