#!/usr/bin/env python3
"""Plots alpha* and d(alpha*)/d(phi) along the tilt path of benches/smoothing_path.rs, exact
against smoothed (Options::smoothing), into docs/img/smoothing_path.png.

    cargo bench --bench smoothing_path          # writes docs/data/smoothing_path.csv
    python3 scripts/plot_smoothing.py           # needs matplotlib
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

src = sys.argv[1] if len(sys.argv) > 1 else "docs/data/smoothing_path.csv"
out = sys.argv[2] if len(sys.argv) > 2 else "docs/img/smoothing_path.png"
rows = defaultdict(list)
with open(src) as f:
    for r in csv.DictReader(f):
        rows[float(r["mu"])].append(
            (float(r["phi_deg"]), float(r["alpha"]), float(r["dalpha_dphi"]), r["kind"])
        )

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
for mu in sorted(rows, key=lambda m: (m != 0.0, -m)):
    pts = sorted(rows[mu])
    phi = [p[0] for p in pts]
    label = "exact" if mu == 0.0 else f"smoothed, mu = {mu:g}"
    style = dict(lw=2.2, color="black") if mu == 0.0 else dict(lw=1.4)
    ax1.plot(phi, [p[1] for p in pts], label=label, **style)
    ax2.plot(phi, [p[2] for p in pts], label=label, **style)
    if mu == 0.0:
        odd = [p for p in pts if p[3] != "Exact"]
        if odd:
            ax2.plot([p[0] for p in odd], [p[2] for p in odd], "o", color="red", ms=7, zorder=5,
                     label="face on face: smoothed (x* not unique)")
ax1.set_xlabel("tilt of the small cube, phi [deg]")
ax1.set_ylabel("alpha*")
ax1.set_title("alpha* through face-against-face contact")
ax2.set_xlabel("tilt of the small cube, phi [deg]")
ax2.set_ylabel("d alpha* / d phi [1/rad]")
ax2.set_title("its derivative: a jump at phi = 0, smoothed across it")
for ax in (ax1, ax2):
    ax.grid(alpha=0.3)
ax2.legend(fontsize=8)
fig.tight_layout()
fig.savefig(out, dpi=110)
print("wrote", out)
