#!/usr/bin/env python3
"""Plot of the iLQR example (`spatial-ilqr --out DIR`): reads DIR/iterations.csv, DIR/trajectory.csv and
DIR/summary.json and writes DIR/ilqr.png: the cost per iteration of the solver fed by the analytical derivatives and
by finite differences (log scale), and the analytical solution's joint positions and torques against the limits.

Needs matplotlib (scripts/peers.sh installs it into build/venv); without it, prints a message and exits 0.
Usage: tools/plot_ilqr.py [DIR]   (default build/report/ilqr)
"""

import csv
import json
import os
import sys


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "build/report/ilqr"
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_ilqr.py: matplotlib is not installed; no plot")
        return 0
    with open(os.path.join(out, "iterations.csv")) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(out, "trajectory.csv")) as f:
        traj = list(csv.reader(f))
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    header, data = traj[0], [[float(x) for x in r] for r in traj[1:]]
    t = [r[0] for r in data]

    fig, axes = plt.subplots(1, 3, figsize=(16, 4.5))
    ax = axes[0]
    for name, style in (("analytical", "o-"), ("finite_differences", "x--")):
        its = [r for r in rows if r["derivatives"] == name]
        v = summary["variants"][name]
        label = f"{name.replace('_', ' ')} ({v['median_iteration_ms']:.2f} ms/iteration)"
        ax.semilogy([int(r["iteration"]) for r in its], [float(r["cost"]) for r in its], style, ms=3, label=label)
    ax.set_xlabel("iteration")
    ax.set_ylabel("cost")
    ax.set_title("iLQR convergence, hoap3_torso (8 joints, 1 s)")
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    for k, (kind, title, unit) in enumerate((("q:", "joint positions", "rad"), ("tau:", "torques", "N m"))):
        ax = axes[k + 1]
        for i, h in enumerate(header):
            if h.startswith(kind):
                ax.plot(t, [r[i] for r in data], label=h.split(":", 1)[1].replace("_joint", ""))
        if kind == "tau:":
            lim = summary["torque_limit"]
            ax.axhline(lim, color="k", ls=":", lw=1)
            ax.axhline(-lim, color="k", ls=":", lw=1)
        ax.set_xlabel("t [s]")
        ax.set_ylabel(unit)
        ax.set_title(title + " (analytical solution)")
        ax.grid(True, alpha=0.3)
    axes[1].legend(fontsize=7, ncol=2)
    fig.tight_layout()
    path = os.path.join(out, "ilqr.png")
    fig.savefig(path, dpi=110)
    print(f"plot_ilqr.py: wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
