#!/usr/bin/env python3
"""Log-log time vs error plot from results/time_vs_error.csv (written by bench_compare).

x = median error (vs a dcol solve at tolerance 1e-12; errors of exactly 0 are drawn at 1e-17),
y = median time per call; one curve per method along its tolerance sweep, single points for the
methods run at their default tolerance.  Usage: plot.py [results_dir]
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-17
out = sys.argv[1] if len(sys.argv) > 1 else "results"
curves = defaultdict(list)
points = []
with open(f"{out}/time_vs_error.csv") as f:
    for row in csv.DictReader(f):
        err, ns = float(row["median_error"]), float(row["median_ns"])
        if err != err:  # NaN
            continue
        err = max(err, FLOOR)
        if row["tolerance"] == "default":
            points.append((row["method"], err, ns))
        else:
            curves[row["method"]].append((err, ns, row["tolerance"]))

fig, ax = plt.subplots(figsize=(8, 5.5))
for name, pts in curves.items():
    pts.sort()
    ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=f"{name} (tolerance sweep)")
    for err, ns, tol in pts:
        ax.annotate(tol, (err, ns), textcoords="offset points", xytext=(4, 4), fontsize=7)
for name, err, ns in points:
    ax.plot([err], [ns], "s", label=name)
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xlabel("median error (|alpha| or |distance| vs dcol at 1e-12; 0 drawn at 1e-17)")
ax.set_ylabel("median time per call [ns]")
ax.set_title("dcol vs Coal 3 and FCL 0.7: time vs error (28 pair types Coal and FCL support)")
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=7, loc="best")
fig.tight_layout()
fig.savefig(f"{out}/time_vs_error.png", dpi=120)
print(f"wrote {out}/time_vs_error.png")
