#!/usr/bin/env python3
"""Plots the heights over time of the falling-objects scene of the engine adapters.

    python3 scripts/plot_engines.py [BUILD_DIR] [OUT_PNG]

Runs `ode_adapter_tests drop halfspace --csv` and `bullet_scenes drop halfspace --csv` from BUILD_DIR
(default build/cmake; the adapters are built when CMake finds ODE and Bullet) and draws each body's
height over time, one panel per engine, with its analytic rest height dashed. OUT_PNG defaults
to docs/img/engines_drop.png. Needs matplotlib. An engine whose program is missing is skipped.
"""
import csv
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

REST = {"sphere": 0.2, "box": 0.1, "capsule": 0.1, "cylinder": 0.15, "cone": 0.1, "ellipsoid": 0.12}
ENGINES = [("ODE", "integrations/ode/tests/ode_adapter_tests"), ("Bullet", "integrations/bullet/tests/bullet_scenes")]


def run(program, csv_path):
    subprocess.run([program, "drop", "halfspace", "--csv", csv_path], check=True, stdout=subprocess.DEVNULL)
    with open(csv_path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0][1:]
    data = [[float(v) for v in r] for r in rows[1:]]
    t = [r[0] for r in data]
    return t, {n: [r[i + 1] for r in data] for i, n in enumerate(names)}


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build/cmake"
    out = sys.argv[2] if len(sys.argv) > 2 else "docs/img/engines_drop.png"
    found = [(name, os.path.join(build, p)) for name, p in ENGINES if os.path.exists(os.path.join(build, p))]
    if not found:
        sys.exit(f"no adapter program under {build}: build with ODE and/or Bullet installed")
    fig, axes = plt.subplots(1, len(found), figsize=(6 * len(found), 4.2), sharey=True, squeeze=False)
    with tempfile.TemporaryDirectory() as tmp:
        for ax, (engine, program) in zip(axes[0], found):
            t, heights = run(program, os.path.join(tmp, engine + ".csv"))
            for i, (name, z) in enumerate(heights.items()):
                color = f"C{i}"
                ax.plot(t, z, color=color, label=name)
                ax.axhline(REST[name], color=color, ls="--", lw=0.8)
            ax.set_title(f"{engine} with dcol contacts: drop on a dcol half-space")
            ax.set_xlabel("time (s)")
            ax.grid(alpha=0.3)
        axes[0][0].set_ylabel("height of the centre (m); dashed: analytic rest height")
        axes[0][0].legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
