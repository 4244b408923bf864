#!/usr/bin/env python3
"""Turns the CSVs written by the application examples (examples/applications) into PNGs.

    python3 scripts/plot_applications.py [CSV_DIR] [OUT_DIR]

CSV_DIR defaults to build/cmake/examples/applications (where ctest runs the examples), OUT_DIR
to docs/img. Needs matplotlib (pip install matplotlib). Missing CSVs are skipped.

Trajectory CSVs start with "# obstacle TYPE X Y Z YAW PARAMS..." and "# robot TYPE PARAMS..."
lines; the obstacles are drawn as the silhouettes (convex hulls of sampled boundary points) of
the convex primitives in the chosen view.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402


def hull(points):
    """Andrew's monotone chain: the convex hull of 2D points, counter-clockwise."""
    pts = sorted(set(points))
    if len(pts) <= 2:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def sphere_points(r, n=24):
    out = []
    for i in range(n + 1):
        th = math.pi * i / n
        for j in range(2 * n):
            ph = math.pi * j / n
            out.append((r * math.sin(th) * math.cos(ph), r * math.sin(th) * math.sin(ph), r * math.cos(th)))
    return out


def circle_x(x, r, n=48):  # a circle of radius r in the plane x = const (axis e_x)
    return [(x, r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n)) for k in range(n)]


def body_points(kind, p):
    """Boundary points (body frame) of a primitive, as in CONVENTIONS.md."""
    if kind == "box":
        a, b, c = p
        return [(sx * a, sy * b, sz * c) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    if kind == "sphere":
        return sphere_points(p[0])
    if kind == "cylinder":
        r, l = p
        return circle_x(-l / 2, r) + circle_x(l / 2, r)
    if kind == "capsule":
        r, l = p
        return [(x + s * l / 2, y, z) for s in (-1, 1) for (x, y, z) in sphere_points(r)]
    if kind == "cone":
        h, beta = p
        return [(-0.75 * h, 0.0, 0.0)] + circle_x(0.25 * h, h * math.tan(beta))
    if kind == "ellipsoid":
        a, b, c = p
        return [(a * x, b * y, c * z) for (x, y, z) in sphere_points(1.0)]
    if kind == "polygon":
        a, b, r = p
        return [(sx * a + x, sy * b + y, z) for sx in (-1, 1) for sy in (-1, 1) for (x, y, z) in sphere_points(r, 8)]
    raise ValueError("unknown shape " + kind)


def quat_rotate(q, v):
    w, x, y, z = q
    R = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    return tuple(sum(R[i][k] * v[k] for k in range(3)) for i in range(3))


def yaw_quat(yaw):
    return (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))


def mrp_quat(p):
    s = sum(c * c for c in p)
    return ((1 - s) / (1 + s),) + tuple(2 * c / (1 + s) for c in p)


def silhouette(kind, params, pos, q, axes):
    pts = []
    for b in body_points(kind, params):
        w = quat_rotate(q, b)
        world = [pos[i] + w[i] for i in range(3)]
        pts.append((world[axes[0]], world[axes[1]]))
    return hull(pts)


def read_trajectory(path):
    obstacles, robot, rows = [], None, []
    with open(path) as f:
        lines = f.read().splitlines()
    body = []
    for line in lines:
        if line.startswith("# obstacle "):
            t = line.split()[2:]
            obstacles.append((t[0], [float(v) for v in t[1:5]], [float(v) for v in t[5:]]))
        elif line.startswith("# robot "):
            t = line.split()[2:]
            robot = (t[0], [float(v) for v in t[1:]])
        else:
            body.append(line)
    for r in csv.DictReader(body):
        rows.append({k: float(v) for k, v in r.items()})
    return obstacles, robot, rows


def draw_obstacles(ax, obstacles, axes):
    for kind, (x, y, z, yaw), params in obstacles:
        poly = silhouette(kind, params, (x, y, z), yaw_quat(yaw), axes)
        ax.add_patch(Polygon(poly, closed=True, facecolor="0.75", edgecolor="0.35", lw=0.8))


def finish(ax, title, xlabel, ylabel, xlim=None, ylim=None):
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_aspect("equal")
    if xlim:
        ax.set_xlim(*xlim)
    if ylim:
        ax.set_ylim(*ylim)


def plot_piano(path, out):
    obstacles, robot, rows = read_trajectory(path)
    fig, ax = plt.subplots(figsize=(6, 6))
    draw_obstacles(ax, obstacles, (0, 1))
    n = len(rows)
    for k, r in enumerate(rows):
        if k % 3 and k != n - 1:
            continue
        poly = silhouette(robot[0], robot[1], (r["x"], r["y"], 0.0), yaw_quat(r["yaw"]), (0, 1))
        c = plt.cm.viridis(k / (n - 1))
        ax.add_patch(Polygon(poly, closed=True, facecolor=c, edgecolor=c, alpha=0.7, lw=0.5))
    ax.plot([r["x"] for r in rows], [r["y"] for r in rows], "r.-", ms=3, lw=0.8)
    finish(ax, "Piano mover: every third knot (top view)", "x [m]", "y [m]", (-3.5, 2.0), (-0.7, 4.0))
    fig.savefig(out, dpi=120, bbox_inches="tight")
    plt.close(fig)


def plot_cone(path, out):
    obstacles, robot, rows = read_trajectory(path)
    fig, axs = plt.subplots(1, 3, figsize=(17, 5), gridspec_kw={"width_ratios": [4, 4, 2.6]})
    n = len(rows)
    for ax, axes, name in ((axs[0], (0, 1), "top view"), (axs[1], (0, 2), "side view")):
        draw_obstacles(ax, obstacles, axes)
        for k, r in enumerate(rows):
            if k % 2 and k != n - 1:
                continue
            q = mrp_quat((r["p1"], r["p2"], r["p3"]))
            poly = silhouette(robot[0], robot[1], (r["x"], r["y"], r["z"]), q, axes)
            c = plt.cm.plasma(k / (n - 1))
            ax.add_patch(Polygon(poly, closed=True, fill=False, edgecolor=c, lw=0.9))
        finish(ax, "Cone through a wall: " + name, "x [m]", "yz"[axes[1] - 1] + " [m]", (-2.0, 2.0), (-1.2, 1.2))
    # Face-on (looking along +x): the hole and, at every knot, the part of the cone inside the
    # wall's slab |x| <= 0.05 (the convex hull of sampled surface points in the slab, projected on
    # the y-z plane): what has to fit through the hole. (The whole cone's silhouette does not
    # fit: the tilted base sticks out of the slab in x.)
    ax = axs[2]
    draw_obstacles(ax, obstacles, (1, 2))
    h, beta = robot[1]
    rad = h * math.tan(beta)
    surface = [(-0.75 * h + s * h, s * rad * math.cos(t), s * rad * math.sin(t))
               for s in [i / 60 for i in range(61)] for t in [2 * math.pi * j / 120 for j in range(120)]]
    surface += [(0.25 * h, f * rad * math.cos(t), f * rad * math.sin(t))
                for f in [i / 20 for i in range(21)] for t in [2 * math.pi * j / 120 for j in range(120)]]
    for k, r in enumerate(rows):
        q = mrp_quat((r["p1"], r["p2"], r["p3"]))
        pts = []
        for b in surface:
            w = quat_rotate(q, b)
            if abs(r["x"] + w[0]) <= 0.05:
                pts.append((r["y"] + w[1], r["z"] + w[2]))
        if len(pts) < 3:
            continue
        c = plt.cm.plasma(k / (n - 1))
        ax.add_patch(Polygon(hull(pts), closed=True, fill=False, edgecolor=c, lw=0.9))
    finish(ax, "face-on: the cone inside the wall's slab", "y [m]", "z [m]", (-0.8, 0.8), (-0.8, 0.8))
    fig.savefig(out, dpi=120, bbox_inches="tight")
    plt.close(fig)


def plot_quadrotor(path, out):
    obstacles, robot, rows = read_trajectory(path)
    fig, axs = plt.subplots(3, 1, figsize=(11, 11), gridspec_kw={"height_ratios": [1, 1, 0.9]})
    fig.subplots_adjust(hspace=0.4)
    n = len(rows)
    for ax, axes, name in ((axs[0], (0, 1), "top view"), (axs[1], (0, 2), "side view")):
        # The hallway's floor, ceiling and walls (the first four obstacles) frame the view.
        draw_obstacles(ax, obstacles[4:], axes)
        for k, r in enumerate(rows):
            q = mrp_quat((r["p1"], r["p2"], r["p3"])) if "p1" in r else (1.0, 0.0, 0.0, 0.0)
            poly = silhouette(robot[0], robot[1], (r["x"], r["y"], r["z"]), q, axes)
            c = plt.cm.viridis(k / (n - 1))
            ax.add_patch(Polygon(poly, closed=True, fill=False, edgecolor=c, lw=0.6))
        ax.plot([r["xyz"[axes[0]]] for r in rows], [r["xyz"[axes[1]]] for r in rows], "r.-", ms=3, lw=0.8)
        lim = (-1.5, 1.5) if axes[1] == 1 else (0.0, 3.0)
        finish(ax, "6-DOF quadrotor (flat ellipsoid) through a hallway: " + name, "x [m]",
               "yz"[axes[1] - 1] + " [m]", (-0.3, 10.3), lim)
    ax = axs[2]
    if "u1" in rows[0]:
        t = [r["t"] for r in rows[:-1]]
        for i in range(1, 5):
            ax.step(t, [r["u%d" % i] for r in rows[:-1]], where="post", lw=1, label="rotor %d" % i)
        hover = 0.5 * 9.81 / 4
        ax.axhline(hover, color="k", ls=":", lw=0.8, label="hover %.3f N" % hover)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("rotor thrust [N]")
        ax.set_title("Rotor thrusts (held constant over each interval)")
        ax.legend(fontsize=8, ncol=5)
    fig.savefig(out, dpi=120, bbox_inches="tight")
    plt.close(fig)


def plot_physics(path, out):
    with open(path) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    t = [r["t"] for r in rows]
    fig, axs = plt.subplots(3, 1, figsize=(9, 10), sharex=True)
    for key in rows[0]:
        if key.startswith("z_"):
            axs[0].plot(t, [r[key] for r in rows], lw=1, label=key[2:])
    axs[0].set_ylabel("height of the origin [m]")
    axs[0].legend(fontsize=7, ncol=4)
    for key, style in (("kinetic", "--"), ("potential", ":"), ("energy", "-")):
        axs[1].plot(t, [r[key] for r in rows], style, label=key)
    axs[1].set_ylabel("energy [J]")
    axs[1].legend()
    axs[2].plot(t, [r["min_alpha"] - 1.0 for r in rows], lw=1)
    axs[2].axhline(-1e-6, color="r", lw=0.8, label="-1e-6 (the bar)")
    axs[2].set_yscale("symlog", linthresh=1e-9)
    axs[2].set_ylabel("min alpha* - 1 after the step")
    axs[2].set_xlabel("t [s]")
    axs[2].legend()
    axs[0].set_title("Contact physics: 12 primitives in a box, 100 Hz")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    plt.close(fig)


def read_free_region(path):
    """The free_region CSV: obstacles with full quaternions, the seed, the regions (centre and
    the lower-triangular L), and the Ipopt histories."""
    obstacles, regions, seed, body = [], {}, None, []
    with open(path) as f:
        for line in f.read().splitlines():
            t = line.split()
            if line.startswith("# obstacle "):
                obstacles.append((t[2], [float(v) for v in t[3:6]], [float(v) for v in t[6:10]],
                                  [float(v) for v in t[10:]]))
            elif line.startswith("# seed "):
                seed = [float(v) for v in t[2:5]]
            elif line.startswith("# contact "):
                regions.setdefault("contacts", []).append([float(v) for v in t[2:]])
            elif line.startswith("# "):
                regions[t[1]] = [float(v) for v in t[2:]]
            else:
                body.append(line)
    history = list(csv.DictReader(body))
    return obstacles, seed, regions, history


def free_region_points(kind, p):
    """Boundary points (body frame) of the free_region obstacles (a hull: radius, count, points)."""
    if kind == "hull":
        r, n = p[0], int(p[1])
        pts = [tuple(p[2 + 3 * i:5 + 3 * i]) for i in range(n)]
        if r > 0:
            return [(a + x, b + y, c + z) for (a, b, c) in pts for (x, y, z) in sphere_points(r, 6)]
        return pts
    return body_points(kind, p)


def ellipsoid_outline(region, axes):
    pts = [(p[axes[0]], p[axes[1]]) for p in ellipsoid_points(region, 36)]
    return hull(pts)


def ellipsoid_points(region, n=12):
    c, l = region[:3], region[3:]
    L = [[l[0], 0.0, 0.0], [l[1], l[2], 0.0], [l[3], l[4], l[5]]]
    return [tuple(c[i] + L[i][0] * x + L[i][1] * y + L[i][2] * z for i in range(3))
            for (x, y, z) in sphere_points(1.0, n)]


def plot_free_region(path, out):
    obstacles, seed, regions, history = read_free_region(path)
    fig, axs = plt.subplots(1, 3, figsize=(17, 5.2), gridspec_kw={"width_ratios": [4, 3.6, 3.4]})
    # The obstacles the region touches (alpha* within 1e-6 of 1) and the contact points.
    contacts = [c for c in regions.get("contacts", []) if c[1] < 1.0 + 1e-6]
    touching = {int(c[0]) for c in contacts}
    views = ((axs[0], (0, 1), "top view (x, y)", (-2.0, 2.0)), (axs[1], (0, 2), "side view (x, z)", (0.0, 2.5)))
    for ax, axes, name, vlim in views:
        # Silhouettes (projections: an overlap in the picture is not one in space); the room's six
        # walls are its outline.
        ax.add_patch(plt.Rectangle((-2.0, vlim[0]), 4.0, vlim[1] - vlim[0], fill=False, lw=1.5, ec="0.2"))
        for j, (kind, pos, q, params) in enumerate(obstacles):
            if j < 6:
                continue
            pts = []
            for b in free_region_points(kind, params):
                w = quat_rotate(q, b)
                pts.append((pos[axes[0]] + w[axes[0]], pos[axes[1]] + w[axes[1]]))
            color = "0.55" if j in touching else "0.85"
            ax.add_patch(Polygon(hull(pts), closed=True, facecolor=color, edgecolor="0.3", lw=0.8))
        for key, style in (("sampled", dict(fill=False, ec="tab:orange", ls="--", lw=1.4)),
                           ("held", dict(fill=False, ec="tab:green", ls="-.", lw=1.4)),
                           ("region", dict(facecolor="tab:blue", alpha=0.3, ec="tab:blue", lw=1.5))):
            if key in regions:
                ax.add_patch(Polygon(ellipsoid_outline(regions[key], axes), closed=True, **style))
        ax.plot([c[2 + axes[0]] for c in contacts], [c[2 + axes[1]] for c in contacts], "o",
                color="tab:red", ms=5)
        ax.plot([seed[axes[0]]], [seed[axes[1]]], "k*", ms=10)
        finish(ax, "Free region: " + name, "x [m]", "yz"[axes[1] - 1] + " [m]", (-2.1, 2.1),
               (vlim[0] - 0.1, vlim[1] + 0.1))
    ax = axs[2]
    for run, label, color in (("free", "centre free (the region)", "tab:blue"),
                              ("held", "centre held at the seed", "tab:green")):
        rows = [r for r in history if r["run"] == run]
        ax.plot([float(r["iteration"]) for r in rows], [float(r["volume"]) for r in rows], ".-",
                color=color, label=label)
    if "sampled" in regions:
        s = regions["sampled"]
        vol = 4.0 / 3.0 * math.pi * s[3] * s[5] * s[8]
        ax.axhline(vol, color="tab:orange", ls="--", label="best of 200 sampled ellipsoids (%.2f m$^3$)" % vol)
    ax.set_yscale("log")
    ax.set_xlabel("Ipopt iteration")
    ax.set_ylabel("ellipsoid volume [m$^3$]")
    ax.set_title("Volume during the solve")
    ax.legend(fontsize=8, loc="lower right")
    fig.savefig(out, dpi=120, bbox_inches="tight")
    plt.close(fig)


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else "build/cmake/examples/applications"
    dst = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
    os.makedirs(dst, exist_ok=True)
    jobs = (("piano_mover", plot_piano), ("cone_through_wall", plot_cone),
            ("quadrotor_hallway", plot_quadrotor), ("contact_physics", plot_physics),
            ("free_region", plot_free_region))
    for name, fn in jobs:
        path = os.path.join(src, name + ".csv")
        if not os.path.exists(path):
            print("skipped (no %s)" % path)
            continue
        out = os.path.join(dst, "app_" + name + ".png")
        fn(path, out)
        print("wrote", out)


if __name__ == "__main__":
    main()
