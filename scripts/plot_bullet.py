#!/usr/bin/env python3
"""Plots the Bullet scenes written with Bullet's own shapes, native narrow phase against dcol's.

    python3 scripts/plot_bullet.py [BUILD_DIR] [OUT_PNG]

Runs `bullet_physics pyramid|pile|slope native|dcol --csv` from BUILD_DIR (default
build/cmake-normal; built when CMake finds Bullet) and draws three panels: the pyramid's largest
box displacement over time, the pile's body heights over time, and the distance travelled down the
slope by each body with its analytic curve. OUT_PNG defaults to docs/img/bullet_scenes.png. Needs
matplotlib.
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

PROGRAM = "integrations/bullet/tests/bullet_physics"
G, THETA = 9.81, math.pi / 6
SLOPE_ACCEL = {
    "box_mu0.8": 0.0,
    "box_mu0.3": G * (math.sin(THETA) - 0.3 * math.cos(THETA)),
    "sphere": 5 / 7 * G * math.sin(THETA),
    "cylinder": 2 / 3 * G * math.sin(THETA),
}


def run(program, scene, mode, path):
    subprocess.run([program, scene, mode, "--csv", path], check=True, stdout=subprocess.DEVNULL)
    with open(path, newline="") as f:
        return list(csv.reader(f))


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build/cmake-normal"
    out = sys.argv[2] if len(sys.argv) > 2 else "docs/img/bullet_scenes.png"
    program = os.path.join(build, PROGRAM)
    if not os.path.exists(program):
        sys.exit(f"{program} not found: build with Bullet installed")
    fig, (ax_pyr, ax_pile, ax_slope) = plt.subplots(1, 3, figsize=(17, 4.6))
    styles = {"native": dict(color="C0", ls="--"), "dcol": dict(color="C3", ls="-")}
    with tempfile.TemporaryDirectory() as tmp:
        for mode in ("native", "dcol"):
            rows = run(program, "pyramid", mode, os.path.join(tmp, "pyr.csv"))[1:]
            t = [float(r[0]) for r in rows]
            ax_pyr.plot(t, [1e3 * float(r[2]) for r in rows], label=mode, **styles[mode])

            rows = run(program, "pile", mode, os.path.join(tmp, "pile.csv"))
            data = [[float(v) for v in r] for r in rows[1:]]
            t = [r[0] for r in data]
            for j in range(1, len(rows[0])):
                ax_pile.plot(t, [r[j] for r in data], lw=0.6, alpha=0.7, label=mode if j == 1 else None,
                             **styles[mode])

            rows = run(program, "slope", mode, os.path.join(tmp, "slope.csv"))[1:]
            bodies = {}
            for name, tt, s in rows:
                bodies.setdefault(name, ([], []))
                bodies[name][0].append(float(tt))
                bodies[name][1].append(float(s))
            for i, (name, (tt, s)) in enumerate(bodies.items()):
                kw = dict(styles[mode])
                kw["color"] = f"C{i}"
                ax_slope.plot(tt, s, label=f"{name} ({mode})", **kw)
                if mode == "dcol":
                    a = SLOPE_ACCEL[name]
                    ax_slope.plot(tt, [0.5 * a * x * x for x in tt], color="k", lw=0.6, ls=":")
    ax_pyr.axhline(5, color="k", lw=0.8, ls=":")
    ax_pyr.set_title("pyramid of 55 boxes: largest displacement (limit 5 mm)")
    ax_pyr.set_xlabel("time (s)")
    ax_pyr.set_ylabel("mm")
    ax_pyr.legend()
    ax_pile.set_title("pile of 49 bodies in a bin: height of each centre")
    ax_pile.set_xlabel("time (s)")
    ax_pile.set_ylabel("m")
    ax_pile.legend()
    ax_slope.set_title("30 degree slope: distance down the slope (dotted: analytic)")
    ax_slope.set_xlabel("time (s)")
    ax_slope.set_ylabel("m")
    ax_slope.set_xlim(0, 1.2)
    ax_slope.legend(fontsize=7)
    for ax in (ax_pyr, ax_pile, ax_slope):
        ax.grid(alpha=0.3)
    fig.suptitle("Bullet with its own shapes: native narrow phase (dashed) and dcol's (solid, use_dcol)")
    fig.tight_layout()
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    fig.savefig(out, dpi=100)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
