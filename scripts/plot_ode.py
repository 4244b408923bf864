#!/usr/bin/env python3
"""Plots ODE's scenes written with its own geoms, native narrow phase against dcol's.

    python3 scripts/plot_ode.py [BUILD_DIR] [OUT_PNG]

Runs `ode_engine_scenes pyramid|pile|slope native|dcol --csv` from BUILD_DIR (default
build/cmake-normal; built when CMake finds ODE) and draws, native solid and dcol dashed:
the pyramid's top box height and largest displacement over time; the heights of six bodies of
the pile's top layer (a sphere, a box, a capsule, a cylinder and two hulls); the distance
travelled down the 30 degree slope by the box (friction 0.8 and 0.3), the sphere and the cylinder,
with the analytic distance dotted. OUT_PNG defaults to docs/img/ode_scenes.png. Needs matplotlib.
"""
import csv
import math
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PROGRAM = "integrations/ode/tests/ode_engine_scenes"
PILE_BODIES = [(36, "sphere"), (37, "box"), (38, "capsule"), (39, "cylinder"), (40, "hull"), (41, "hull")]


def run(program, scene, mode, tmp):
    path = os.path.join(tmp, f"{scene}_{mode}.csv")
    subprocess.run([program, scene, mode, "--csv", path], check=True, stdout=subprocess.DEVNULL)
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0]
    data = [[float(v) for v in r] for r in rows[1:]]
    return {n: [r[i] for r in data] for i, n in enumerate(names)}


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build/cmake-normal"
    out = sys.argv[2] if len(sys.argv) > 2 else "docs/img/ode_scenes.png"
    program = os.path.join(build, PROGRAM)
    if not os.path.exists(program):
        sys.exit(f"{program} not found: build with CMake first (ODE is needed)")
    with tempfile.TemporaryDirectory() as tmp:
        runs = {(s, m): run(program, s, m, tmp) for s in ("pyramid", "pile", "slope") for m in ("native", "dcol")}
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    styles = {"native": "-", "dcol": "--"}

    ax = axes[0]
    for mode in ("native", "dcol"):
        d = runs[("pyramid", mode)]
        ax.plot(d["t"], [1e3 * x for x in d["max_displacement"]], styles[mode], color="C0",
                label=f"largest displacement, {mode}")
        ax.plot(d["t"], [1e3 * (z - 1.9) for z in d["top_z"]], styles[mode], color="C3",
                label=f"top box height - 1.9 m, {mode}")
    ax.axhline(5, color="gray", lw=0.8, ls=":")
    ax.set_title("pyramid of 55 boxes on ODE's plane")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("mm")
    ax.legend(fontsize=7)

    ax = axes[1]
    for k, (i, name) in enumerate(PILE_BODIES):
        for mode in ("native", "dcol"):
            d = runs[("pile", mode)]
            ax.plot(d["t"], d[f"z{i}"], styles[mode], color=f"C{k}", lw=1,
                    label=f"{name} {i}" if mode == "native" else None)
    ax.set_title("pile of 48 bodies: top layer's heights (native solid, dcol dashed)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("height of the centre (m)")
    ax.legend(fontsize=7)

    ax = axes[2]
    g, th = 9.81, math.radians(30)
    accel = {"box_mu08": 0.0, "box_mu03": g * (math.sin(th) - 0.3 * math.cos(th)),
             "sphere": 5 / 7 * g * math.sin(th), "cylinder": 2 / 3 * g * math.sin(th)}
    labels = {"box_mu08": "box, friction 0.8", "box_mu03": "box, friction 0.3", "sphere": "sphere",
              "cylinder": "cylinder"}
    for k, key in enumerate(accel):
        for mode in ("native", "dcol"):
            d = runs[("slope", mode)]
            ax.plot(d["t"], d[key], styles[mode], color=f"C{k}", label=f"{labels[key]}" if mode == "native" else None)
        t = runs[("slope", "native")]["t"]
        ax.plot(t, [0.5 * accel[key] * x * x for x in t], ":", color="black", lw=0.8)
    ax.set_title("30 degree slope (analytic dotted)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("distance down the slope (m)")
    ax.legend(fontsize=7)

    fig.suptitle("ODE 0.16 with its own geoms: native narrow phase (solid) against dcol_ode::use_dcol() (dashed)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
