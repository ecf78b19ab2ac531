#!/usr/bin/env python3
"""Plots of the closed-loop walk: reads DIR/walk.csv and DIR/walk.json written by `spatial-dyn walk --out DIR`
(which runs this script itself) and writes PNGs next to them:

    walk_top.png        top view (x forward, y left): every footprint as its sole rectangle, the reference ZMP, the
                        cart-table and multibody ZMP of the plan, the simulated centre of pressure, the CoM and pelvis
    walk_torques.png    per joint, |τ| over time against the motor's rated and maximum torque
    walk_zmp_error.png  ZMP errors over time (first stage, after the second stage, simulated CoP), then the CoP's
                        margin in the support polygon and the normal forces of the ground on both soles

Joint names are read from the CSV header (the tau:<joint> columns). Needs matplotlib (scripts/peers.sh installs it
into build/venv); without it, prints a message and exits 0.
Usage: tools/plot_walk.py [DIR]   (default build/report/walk)
"""

import json
import math
import os
import sys

from plot_scenes import joints_of, read_csv, short

FEET = {"left": "tab:blue", "right": "tab:red"}


def load(d):
    """(columns as numpy arrays, walk.json, joint names in CSV order)."""
    import numpy as np
    header, cols = read_csv(os.path.join(d, "walk.csv"))
    with open(os.path.join(d, "walk.json")) as f:
        summary = json.load(f)
    return {k: np.asarray(v) for k, v in cols.items()}, summary, joints_of(header, "tau")


def xy(c, name):
    return c[name + ":x"], c[name + ":y"]


def distance(c, a, b):
    """|a − b| in the ground plane, mm (NaN where either is NaN)."""
    import numpy as np
    (ax, ay), (bx, by) = xy(c, a), xy(c, b)
    return 1e3 * np.hypot(ax - bx, ay - by)


def sole_outline(step, sole):
    """Closed outline (xs, ys) of a footprint's sole rectangle in the world."""
    cy, sy = math.cos(step["yaw"]), math.sin(step["yaw"])
    corners = [(sole["front"], sole["left"]), (sole["front"], -sole["right"]), (-sole["back"], -sole["right"]),
               (-sole["back"], sole["left"]), (sole["front"], sole["left"])]
    return ([step["x"] + cy * u - sy * v for u, v in corners], [step["y"] + sy * u + cy * v for u, v in corners])


def mm(v):
    return f"{v * 1e3:.1f} mm" if v is not None else "–"


def describe(p):
    """'8 steps of 50 mm, turn 0.15 rad/step' from walk.json's parameters."""
    turn = f", turn {p['turn']:g} rad/step" if p.get("turn") else ", straight"
    return f"{p['steps']} steps of {p['length'] * 1e3:.0f} mm{turn}"


def shade_double_support(ax, c):
    """Grey background where both soles touch the ground."""
    both = (c["contact:left"] > 0.5) & (c["contact:right"] > 0.5)
    ax.fill_between(c["t"], 0, 1, where=both, color="0.9", transform=ax.get_xaxis_transform(), step="mid",
                    linewidth=0)


def plot_top(plt, c, s, out):
    import numpy as np
    sole, p, cl = s["sole"], s["parameters"], s["closed_loop"]
    xs = [x for st in s["footsteps"] for x in sole_outline(st, sole)[0]]
    ys = [y for st in s["footsteps"] for y in sole_outline(st, sole)[1]]
    span_x, span_y = max(xs) - min(xs), max(ys) - min(ys)
    width = 15.0
    fig, ax = plt.subplots(figsize=(width, min(max(width * span_y / span_x + 1.5, 4.0), 12.0)))
    seen = set()
    for k, st in enumerate(s["footsteps"]):
        fx, fy = sole_outline(st, sole)
        label = f"{st['foot']} sole" if st["foot"] not in seen else None
        seen.add(st["foot"])
        ax.fill(fx, fy, color=FEET[st["foot"]], alpha=0.05, linewidth=0)
        ax.plot(fx, fy, color=FEET[st["foot"]], linewidth=1.0, linestyle=":" if k < 2 else "-", label=label)
        ax.plot([st["x"]], [st["y"]], "+", color=FEET[st["foot"]], markersize=6)
        ax.annotate(str(k), (st["x"], st["y"]), xytext=(3, 3), textcoords="offset points", fontsize=8,
                    color=FEET[st["foot"]])
    ax.plot(*xy(c, "zmp_ref"), color="black", linewidth=1.4, label="reference ZMP")
    ax.plot(*xy(c, "zmp_ct"), color="tab:gray", linewidth=0.8, linestyle="--", label="cart-table ZMP")
    ax.plot(*xy(c, "zmp_mb"), color="tab:green", linewidth=1.0, label="multibody ZMP (plan)")
    cx, cy = xy(c, "cop")
    ok = ~(np.isnan(cx) | np.isnan(cy))  # rows without a centre of pressure (no contact) skipped
    ax.plot(cx[ok], cy[ok], color="tab:orange", linewidth=0.6, alpha=0.8, label="simulated CoP")
    ax.plot(*xy(c, "com"), color="tab:purple", linewidth=1.4, label="CoM")
    ax.plot(*xy(c, "pelvis"), color="tab:brown", linewidth=0.8, linestyle="-.", label="pelvis")
    ax.set_aspect("equal")
    ax.set_xlabel("x forward [m]")
    ax.set_ylabel("y left [m]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    status = (f"walked {cl['steps_completed']} / {p['steps']} steps" if cl["walked"]
              else f"FELL after {cl['steps_completed']} / {p['steps']} steps")
    ax.set_title(f"HOAP-3 walk, top view: {describe(p)}, ZMP model {p['zmp_model']}; {status}; closed-loop CoP "
                 f"min margin {mm(cl['cop_min_margin'])}\n(+ and number: foot centre and footstep order; dotted: the "
                 f"initial feet)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=100, bbox_inches="tight")
    plt.close(fig)


def plot_torques(plt, c, s, joints, out):
    import numpy as np
    limits = {e["joint"]: e for e in s["torques"]}
    ncols = 7
    nrows = -(-len(joints) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(3.0 * ncols, 2.3 * nrows + 0.6), sharex=True, squeeze=False)
    t = c["t"]
    for k, ax in enumerate(axes.flat):
        if k >= len(joints):
            ax.axis("off")
            continue
        j = joints[k]
        tau = np.abs(c["tau:" + j])
        ax.plot(t, tau, linewidth=0.6, color="tab:blue")
        lim = limits.get(j)
        top = 0.0 if np.all(np.isnan(tau)) else np.nanmax(tau)
        title = short(j)
        if lim:
            ax.axhline(lim["rated"], color="orange", linestyle="--", linewidth=0.9)
            ax.axhline(lim["maximum"], color="red", linestyle=":", linewidth=0.9)
            top = max(top, lim["maximum"])
            title += f": peak {lim['rated_ratio']:.2f} × rated"
        ax.set_ylim(0, 1.08 * top if top > 0 else 1)
        over = lim is not None and lim["rated_ratio"] > 1
        ax.set_title(title, fontsize=8, color="red" if over else "black")
        ax.tick_params(labelsize=7)
        if k % ncols == 0:
            ax.set_ylabel("|τ| [N m]", fontsize=8)
        if k + ncols >= len(joints):  # the lowest panel of its column
            ax.set_xlabel("time [s]", fontsize=8)
            ax.tick_params(labelbottom=True)
    worst = max(s["torques"], key=lambda e: e["rated_ratio"], default=None)
    extra = (f"; worst {short(worst['joint'])}: {worst['rated_ratio']:.2f} × rated, "
             f"{worst['max_ratio']:.2f} × maximum" if worst else "")
    fig.suptitle(f"Applied joint torques, closed loop ({describe(s['parameters'])}): |τ| against the motor's rated "
                 f"(orange dashed) and maximum (red dotted) torque{extra}", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)


def plot_zmp_error(plt, c, s, out):
    t = c["t"]
    p, passes = s["parameters"], s["open_loop"]["passes"]
    fig, axes = plt.subplots(2, 1, figsize=(14, 8), sharex=True)
    ax = axes[0]
    shade_double_support(ax, c)
    ax.plot(t, distance(c, "zmp_mb0", "zmp_ref"), color="tab:red", linewidth=0.9,
            label="|multibody ZMP − reference|, first stage only")
    ax.plot(t, distance(c, "zmp_mb", "zmp_ref"), color="tab:green", linewidth=1.1,
            label=f"|multibody ZMP − reference|, after the second stage ({p['second_stage_iterations']} iterations)")
    ax.plot(t, distance(c, "zmp_ct", "zmp_ref"), color="tab:gray", linewidth=0.7, linestyle="--",
            label="|cart-table ZMP − reference|")
    ax.plot(t, distance(c, "cop", "zmp_ref"), color="tab:orange", linewidth=0.6, alpha=0.8,
            label="|simulated CoP − reference| (closed loop)")
    ax.set_ylabel("ZMP error [mm]")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    passes_text = ", ".join(f"{e['zmp_error_max'] * 1e3:.1f}/{e['zmp_error_rms'] * 1e3:.1f}" for e in passes)
    ax.set_title(f"ZMP errors ({describe(p)}, ZMP model {p['zmp_model']}); open-loop multibody error max/RMS per "
                 f"pass [mm]: {passes_text or '–'} (grey background: double support)", fontsize=9)

    ax = axes[1]
    shade_double_support(ax, c)
    cl = s["closed_loop"]
    ax.plot(t, 1e3 * c["margin"], color="tab:purple", linewidth=0.9, label="CoP margin in the support polygon")
    ax.axhline(0, color="black", linewidth=0.8)
    ax.set_ylabel("CoP margin [mm]", color="tab:purple")
    ax.set_xlabel("time [s]")
    ax.grid(True, alpha=0.3)
    forces = ax.twinx()
    for foot in ("left", "right"):
        forces.plot(t, c[f"F:{foot}:z"], color=FEET[foot], linewidth=0.7, label=f"normal force, {foot} sole")
    forces.set_ylabel("normal force of the ground [N]")
    forces.set_ylim(bottom=min(0.0, forces.get_ylim()[0]))
    lines = ax.get_legend_handles_labels()
    more = forces.get_legend_handles_labels()
    forces.legend(lines[0] + more[0], lines[1] + more[1], fontsize=7, loc="upper right")
    ax.set_title(f"Closed loop: CoP min margin {mm(cl['cop_min_margin'])}, min normal force "
                 f"{cl['min_normal_force']:.1f} N, max |F_t|/F_n {cl['max_friction_ratio']:.2f} "
                 f"(μ = {p['friction']:g})", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "build/report/walk"
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_walk.py: matplotlib is not installed: no walk plots (run scripts/peers.sh)")
        return 0
    if not all(os.path.exists(os.path.join(d, f)) for f in ("walk.csv", "walk.json")):
        print(f"plot_walk.py: no walk output in {d} (run: spatial-dyn walk --out {d})", file=sys.stderr)
        return 1
    c, summary, joints = load(d)
    written = [os.path.join(d, n) for n in ("walk_top.png", "walk_torques.png", "walk_zmp_error.png")]
    plot_top(plt, c, summary, written[0])
    plot_torques(plt, c, summary, joints, written[1])
    plot_zmp_error(plt, c, summary, written[2])
    for path in written:
        print(f"plot_walk.py: wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
