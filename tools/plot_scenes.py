#!/usr/bin/env python3
"""Plots of the reference study's scenes: reads DIR/<scene>.csv and DIR/<scene>.json written by
`spatial-dyn scene all --out DIR` and writes PNGs next to them:

    <scene>.png           joint positions, torques over the rated torque, accelerations of the trajectory against
                          forward dynamics (CRBA + LTDL, ABA) fed with the RNEA torques, and their difference
    step_resultant.png    resultant force of the ground on the robot and the ZMP against the sole (step)
    pendulum_resultant.png  the same, whole body against the double pendulum (pendulum)

Needs matplotlib (scripts/peers.sh installs it into build/venv); without it, prints a message and exits 0.
Usage: tools/plot_scenes.py [DIR]   (default build/report/scenes)
"""

import csv
import json
import os
import sys


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header, data = rows[0], rows[1:]
    cols = {name: [float(r[i]) for r in data] for i, name in enumerate(header)}
    return header, cols


def joints_of(header, kind):
    return [h.split(":", 1)[1] for h in header if h.startswith(kind + ":")]


def short(joint):
    return joint.replace("_joint", "")


def groups(joints):
    """Joint groups for the panels: arms, stance leg, swing leg, waist."""
    out = {}
    for j in joints:
        side = "right" if (j.startswith("R_") or "_R_" in j) else "left"
        if j.startswith("WAIST_CHEST"):
            g = "waist"
        elif any(k in j for k in ("SFE", "SAA", "SHR", "_EB")):
            g = side + " arm"
        else:
            g = side + " leg"
        out.setdefault(g, []).append(j)
    return out


def plot_scene(plt, d, name):
    header, c = read_csv(os.path.join(d, name + ".csv"))
    with open(os.path.join(d, name + ".json")) as f:
        summary = json.load(f)
    t = c["time"]
    joints = joints_of(header, "q")
    gs = groups(joints)
    order = [g for g in ("right arm", "left arm", "right leg", "left leg", "waist") if g in gs]
    fig, axes = plt.subplots(4, len(order), figsize=(4.2 * len(order), 12), squeeze=False, sharex=True)
    for col, g in enumerate(order):
        ax = axes[0][col]
        for j in gs[g]:
            ax.plot(t, c["q:" + j], label=short(j))
        ax.set_title(f"{g}: position [rad]", fontsize=9)
        ax.legend(fontsize=6)
        ax = axes[1][col]
        for j in gs[g]:
            ax.plot(t, c["tau/rated:" + j], label=short(j))
        for y in (1, -1):
            ax.axhline(y, color="orange", linestyle="--", linewidth=0.8)
        ax.set_title(f"{g}: torque / rated torque (dashed: rated)", fontsize=9)
        ax = axes[2][col]
        for k, j in enumerate(gs[g]):
            line, = ax.plot(t, c["qdd:" + j], linewidth=2, alpha=0.5, label=short(j))
            ax.plot(t, c["qdd_crba:" + j], linestyle="--", color=line.get_color(), linewidth=0.8)
            ax.plot(t, c["qdd_aba:" + j], linestyle=":", color=line.get_color(), linewidth=0.8)
        ax.set_title(f"{g}: q̈ [rad/s²]: trajectory (thick), CRBA (--), ABA (:)", fontsize=9)
        ax = axes[3][col]
        for j in gs[g]:
            ax.semilogy(t, [abs(a - b) or 1e-18 for a, b in zip(c["qdd_crba:" + j], c["qdd:" + j])], linewidth=0.7)
            ax.semilogy(t, [abs(a - b) or 1e-18 for a, b in zip(c["qdd_aba:" + j], c["qdd:" + j])], linewidth=0.7,
                        linestyle=":")
        ax.set_title(f"{g}: |FD q̈ − q̈| [rad/s²] (CRBA solid, ABA dotted)", fontsize=9)
        ax.set_xlabel("time [s]")
    fig.suptitle(f"{summary['title']} ({summary['model']}, {summary['samples']} samples at 2 ms)")
    fig.tight_layout()
    out = os.path.join(d, name + ".png")
    fig.savefig(out, dpi=90)
    plt.close(fig)
    written = [out]

    if "F_z" in c:
        polygon = summary["resultant"]["support_polygon_m"]
        fig, axes = plt.subplots(1, 3 if "pend_F_z" in c else 2, figsize=(16 if "pend_F_z" in c else 11, 4.5))
        ax = axes[0]
        for comp, style in (("F_x", "-"), ("F_y", "-"), ("F_z", "-")):
            ax.plot(t, c[comp], style, label=f"{comp} whole body")
        if "pend_F_z" in c:
            for comp in ("pend_F_x", "pend_F_z"):
                ax.plot(t, c[comp], "--", label=comp.replace("pend_", "") + " pendulum")
        weight = summary["resultant"]["weight_N"]
        ax.axhline(weight, color="gray", linestyle=":", label=f"m g = {weight:.2f} N")
        ax.axhline(summary["study"]["Fz_start_whole_N"], color="red", linestyle=":", linewidth=0.8,
                   label="study: 83.3 N (whole, start)")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("force of the ground on the robot [N] (sole frame)")
        ax.legend(fontsize=7)
        ax.set_title("resultant force")
        if "pend_F_z" in c:
            ax = axes[1]
            ax.plot(t, [a - b for a, b in zip(c["F_z"], c["pend_F_z"])], label="F_z whole − pendulum")
            ax.plot(t, [a - b for a, b in zip(c["F_x"], c["pend_F_x"])], label="F_x whole − pendulum")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("[N]")
            ax.legend(fontsize=7)
            ax.set_title("difference between the models")
        ax = axes[-1]
        x0, x1, y0, y1 = polygon
        ax.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], color="black", label="sole (support polygon)")
        ax.plot(c["zmp_x"], c["zmp_y"], label="ZMP")
        ax.plot(c["com_x"], c["com_y"], linestyle="--", label="CoM projection")
        ax.plot([c["zmp_x"][0]], [c["zmp_y"][0]], "o", color="green", label="start")
        ax.set_aspect("equal")
        ax.set_xlabel("x forward [m]")
        ax.set_ylabel("y left [m]")
        ax.legend(fontsize=7)
        ax.set_title("ZMP against the support polygon")
        fig.tight_layout()
        out = os.path.join(d, name + "_resultant.png")
        fig.savefig(out, dpi=90)
        plt.close(fig)
        written.append(out)
    return written


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "build/report/scenes"
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_scenes.py: matplotlib is not installed: no scene plots (run scripts/peers.sh)")
        return 0
    names = sorted(f[:-5] for f in os.listdir(d) if f.endswith(".json")) if os.path.isdir(d) else []
    if not names:
        print(f"plot_scenes.py: no scene output in {d} (run: spatial-dyn scene all --out {d})")
        return 0
    for name in names:
        if not os.path.exists(os.path.join(d, name + ".csv")):
            continue
        for path in plot_scene(plt, d, name):
            print(f"plot_scenes.py: wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
