#!/usr/bin/env python3
"""Log-log time vs error plot from results/time_vs_error.csv (written by bench_compare).

Two panels over the 28 pair types Coal and FCL support:
 (a) distance: median error on separated cases against an independent reference (FCL at 1e-12
     where it agrees with Coal at 1e-12, else dcol at 1e-12 where it agrees with one of them;
     see benchmark.md) against median time, along the tolerance sweeps of dcol_distance,
     coal::distance and fcl::distance, and the default-tolerance points;
 (b) alpha: dcol_proximity's sweep (and gradient / Jacobian at the default tolerance), errors
     against dcol's own solve at 1e-12 (self-referenced: only dcol computes alpha).
Panel (b) also draws the max error of the sweep (its medians are 0). Median errors of exactly 0 are drawn at FLOOR (marked with an open symbol and counted in the
panel's note), never dropped. Usage: plot.py [results_dir]
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-17
out = sys.argv[1] if len(sys.argv) > 1 else "results"
curves = {"distance": defaultdict(list), "alpha": defaultdict(list)}
points = {"distance": [], "alpha": []}
with open(f"{out}/time_vs_error.csv") as f:
    for row in csv.DictReader(f):
        err, ns = float(row["median_error"]), float(row["median_ns"])
        if err != err:  # NaN: no error measured (e.g. no reference on any case)
            continue
        q = row["quantity"]
        zero_share = float(row["zero_error_share"]) if row["zero_error_share"] else 0.0
        item = (max(err, FLOOR), ns, row["tolerance"], err == 0, zero_share, float(row["max_error"]))
        if row["tolerance"] == "default":
            points[q].append((row["method"],) + item)
        else:
            curves[q][row["method"]].append(item)

fig, axes = plt.subplots(1, 2, figsize=(14, 6))
titles = {
    "distance": "(a) distance, separated cases: error vs an independent reference\n"
    "(FCL@1e-12 = Coal@1e-12 to 1e-9, else dcol@1e-12 agreeing with one)",
    "alpha": "(b) proximity alpha*: error vs dcol's own solve at 1e-12\n(self-referenced: only dcol computes alpha*)",
}
for ax, q in zip(axes, ("distance", "alpha")):
    zeros = []
    for name, pts in curves[q].items():
        pts.sort(key=lambda p: float(p[2]))
        line = ax.plot([p[0] for p in pts], [p[1] for p in pts], "-", label=f"{name} (tolerance sweep)")[0]
        for err, ns, tol, zero, share, _ in pts:
            ax.plot([err], [ns], "o", color=line.get_color(), mfc="none" if zero else line.get_color())
            ax.annotate(tol, (err, ns), textcoords="offset points", xytext=(4, 4), fontsize=7)
            if zero:
                zeros.append(f"{name} @{tol} ({100 * share:.1f} % of errors are 0)")
        if q == "alpha":  # the medians sit at the floor: show the max error too
            ax.plot([max(p[5], FLOOR) for p in pts], [p[1] for p in pts], "x--", color=line.get_color(),
                    alpha=0.6, label=f"{name}: max error")
    for name, err, ns, tol, zero, share, _ in points[q]:
        ax.plot([err], [ns], "s", mfc="none" if zero else None, label=f"{name}")
        if zero:
            zeros.append(f"{name} ({100 * share:.1f} % of errors are 0)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axvline(FLOOR, color="grey", lw=0.8, ls=":")
    ax.set_xlabel(f"median error (open symbols: median 0, drawn at {FLOOR:g})"
                  + ("; x: max error" if q == "alpha" else ""))
    ax.set_ylabel("median time per call [ns]")
    ax.set_title(titles[q], fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    if zeros:
        top = q == "alpha"  # (b): the max-error curve runs along the bottom
        ax.text(0.01, 0.99 if top else 0.01, "median error 0 (at the floor):\n" + "\n".join(zeros),
                transform=ax.transAxes, fontsize=6, va="top" if top else "bottom", ha="left",
                bbox=dict(fc="white", ec="grey", alpha=0.8))
fig.suptitle("dcol vs Coal 3 and FCL 0.7: time vs error (28 pair types Coal and FCL support)")
fig.tight_layout()
fig.savefig(f"{out}/time_vs_error.png", dpi=120)
print(f"wrote {out}/time_vs_error.png")
