"""The README's picture: the embedded default scene ``s2-gyroscope-pole`` —
a gyroscope on the unit sphere whose path crosses the north pole, where the
paper's chart (r, φ) is singular — drawn with ``framedyn.plot.path3d`` (the
body frame e₁, e₂ as arrows along the path).

Run: ``python python/examples/readme_figure.py [OUTPUT.png]`` (default
``docs/figures/readme_gyroscope_pole.png``; needs matplotlib).
"""

import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import framedyn as fd  # noqa: E402
import framedyn.plot  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "docs", "figures", "readme_gyroscope_pole.png")

scene = fd.Scene.example("s2-gyroscope-pole")
sol = fd.solve(scene)
closest = 1.0 - float(sol.position[:, 2].max())
print(f"{len(sol)} records, closest approach to the pole 1 − max z = {closest:.2e}, energy drift {sol.stats['energy_drift']:.2e}")

fig = plt.figure(figsize=(5.5, 5.0))
ax = fig.add_subplot(projection="3d")
fd.plot.path3d(sol, scene, ax=ax, frame_every=20, arrow_length=0.2)
ax.scatter([0], [0], [1], color="k", s=12)
ax.text(0.15, -0.1, 1.2, "north pole", ha="left")
ax.view_init(elev=30, azim=-35)
ax.set_axis_off()
ax.set_box_aspect((1, 1, 1), zoom=1.45)
ax.set_title("gyroscope through the pole (s2-gyroscope-pole)")
fig.tight_layout()
os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
fig.savefig(out, dpi=110)
print(f"wrote {out}")
