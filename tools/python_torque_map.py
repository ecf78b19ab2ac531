#!/usr/bin/env python3
"""Gravity torques of the HOAP-3's stance leg over a grid of poses, against the motor limits: the "user of it" example
of the Python package (issue 14).

The robot stands on its right foot (`spatial.load_urdf(urdf_path("hoap3.urdf"), root="R_SOLE")`, head and wrists
locked at 0: the 21 joints of the stance21 bench model). Over a grid of the right (stance) leg's hip pitch × knee
pitch, within their URDF limits, every other joint at 0, one batch call `spatial.gravity(model, Q)` gives the torques
that hold each pose still; the plot shows the stance leg's hip, knee and ankle pitch torques as contour maps, with the
contour |τ| = the motor's maximum torque (the URDF effort limit) drawn and the region beyond it hatched, and the
contour |τ| = the rated torque (data sheet, quoted in urdf/hoap3.urdf's header comment) dashed.

Writes OUT/torque_map.png (needs matplotlib; without it, says so and writes the JSON only) and OUT/torque_map.json
(per joint: effort limit, rated torque, max |τ| and the pose where it occurs, fraction of the grid beyond the limit
and beyond the rated torque; the grid; the time of the batch call). Prints one line per joint.
Usage: tools/python_torque_map.py [--out build/report/python] [--n 81]
"""

import argparse
import json
import os
import sys
import time

import numpy as np

import spatial

# Head and wrists locked at 0, as for the generated stance models (src/models/CMakeLists.txt).
LOCKED = ["CHEST_H_PAN_joint", "H_PAN_H_TILT_joint", "H_TILT_H_ROLL_joint", "R_EB_R_WR_joint", "L_EB_L_WR_joint"]
ROOT = "R_SOLE"
# The stance (right) leg: the grid's two axes, and the three pitch joints whose torques are mapped.
HIP_PITCH, KNEE, ANKLE_PITCH = "R_LAA_R_LFE_joint", "R_LFE_R_KN_joint", "R_KN_R_AFE_joint"
MAPPED = [("hip pitch", HIP_PITCH), ("knee pitch", KNEE), ("ankle pitch", ANKLE_PITCH)]
# Rated torques [N m] (urdf/hoap3.urdf's header comment, from the data sheet; the URDF effort is the maximum torque).
RATED = {HIP_PITCH: 1.5, KNEE: 2.0, ANKLE_PITCH: 2.0}


def load_model():
    return spatial.load_urdf(spatial.urdf_path("hoap3.urdf"), root=ROOT, lock={j: 0.0 for j in LOCKED})


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="build/report/python", help="output directory (default build/report/python)")
    ap.add_argument("--n", type=int, default=81, help="grid points per axis (default 81)")
    args = ap.parse_args()
    if args.n < 2:
        ap.error("--n must be at least 2")
    os.makedirs(args.out, exist_ok=True)

    model = load_model()
    names = list(model.joint_names)
    for j in (HIP_PITCH, KNEE, ANKLE_PITCH):
        if j not in names:
            sys.exit(f"python_torque_map.py: joint {j} is not in the model (joints: {', '.join(names)})")
    # A fixed base with 1-DoF joints: q, v and τ have one entry per joint, in model.joint_names order.
    if model.floating or not (model.nq == model.nv == len(names)):
        sys.exit(f"python_torque_map.py: expected a fixed-base model with one coordinate per joint, got nq={model.nq} "
                 f"nv={model.nv} joints={len(names)} floating={model.floating}")
    idx = {j: model.joint_index(j) for j in (HIP_PITCH, KNEE, ANKLE_PITCH)}
    lower, upper, effort = (np.asarray(a, dtype=float) for a in (model.lower, model.upper, model.effort))

    hip = np.linspace(lower[idx[HIP_PITCH]], upper[idx[HIP_PITCH]], args.n)
    knee = np.linspace(lower[idx[KNEE]], upper[idx[KNEE]], args.n)
    H, K = np.meshgrid(hip, knee)  # rows: knee, columns: hip
    Q = np.zeros((H.size, model.nq))
    Q[:, idx[HIP_PITCH]] = H.ravel()
    Q[:, idx[KNEE]] = K.ravel()

    tau = np.asarray(spatial.gravity(model, Q))  # one batch call over the whole grid: (n*n, nv)
    times = []  # the time of that call: median of 5 more (the first one pays for first touches)
    for _ in range(5):
        t0 = time.perf_counter()
        spatial.gravity(model, Q)
        times.append(time.perf_counter() - t0)
    batch_s = float(np.median(times))
    if tau.shape != (H.size, model.nv):
        sys.exit(f"python_torque_map.py: spatial.gravity returned shape {tau.shape}, expected {(H.size, model.nv)}")

    joints = []
    maps = {}
    for title, j in MAPPED:
        T = tau[:, idx[j]].reshape(H.shape)
        maps[j] = T
        a = np.abs(T)
        k = int(np.argmax(a))
        limit = float(effort[idx[j]])
        rated = RATED.get(j)
        joints.append({
            "joint": j,
            "title": title,
            "index": idx[j],
            "effort_limit_Nm": limit,
            "rated_Nm": rated,
            "max_abs_tau_Nm": float(a.flat[k]),
            "max_abs_tau_at": {"hip_pitch_rad": float(H.flat[k]), "knee_rad": float(K.flat[k])},
            "min_tau_Nm": float(T.min()),
            "max_tau_Nm": float(T.max()),
            "fraction_beyond_limit": float(np.mean(a > limit)) if limit > 0 else None,
            "fraction_beyond_rated": float(np.mean(a > rated)) if rated else None,
        })

    summary = {
        "model": {"urdf": "hoap3.urdf", "root": ROOT, "locked": LOCKED, "nv": model.nv,
                  "total_mass_kg": float(model.total_mass), "gravity": [float(g) for g in model.gravity]},
        "grid": {"points_per_axis": args.n, "states": int(H.size),
                 "hip_pitch": {"joint": HIP_PITCH, "from_rad": float(hip[0]), "to_rad": float(hip[-1])},
                 "knee": {"joint": KNEE, "from_rad": float(knee[0]), "to_rad": float(knee[-1])},
                 "other_joints": 0.0},
        "batch_call": {"call": "spatial.gravity(model, Q)", "states": int(H.size), "seconds": batch_s,
                       "ns_per_state": batch_s / H.size * 1e9,
                       "timing": "wall time, median of 5 calls after the first"},
        "joints": joints,
        "plot": None,
    }

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.ticker import MaxNLocator
    except ImportError:
        plt = None
        print("python_torque_map.py: matplotlib is not installed; no plot")
    if plt is not None:
        hd, kd = np.degrees(H), np.degrees(K)
        fig, axes = plt.subplots(1, len(MAPPED), figsize=(5.6 * len(MAPPED), 4.9))
        for ax, rec in zip(axes, joints):
            j = rec["joint"]
            T = maps[j]
            limit, rated = rec["effort_limit_Nm"], rec["rated_Nm"]
            vmax = max(float(np.abs(T).max()), limit, 1e-9)
            cf = ax.contourf(hd, kd, T, levels=np.linspace(-vmax, vmax, 25), cmap="RdBu_r")
            cbar = fig.colorbar(cf, ax=ax, label="gravity torque τ [N m]")
            cbar.locator = MaxNLocator(9)
            cbar.update_ticks()
            if np.abs(T).max() > limit > 0:
                big = 2.0 * vmax + 1.0
                ax.contourf(hd, kd, np.abs(T), levels=[limit, big], colors="none", hatches=["///"])
                ax.contour(hd, kd, np.abs(T), levels=[limit], colors="k", linewidths=1.8)
            if rated and np.abs(T).max() > rated:
                ax.contour(hd, kd, np.abs(T), levels=[rated], colors="k", linewidths=1.0, linestyles="--")
            frac = rec["fraction_beyond_limit"] or 0.0
            ax.set_title(f"{rec['title']} ({j.replace('_joint', '')}): max |τ| {rec['max_abs_tau_Nm']:.2f} N m\n"
                         f"limit {limit:g} N m (solid, hatched beyond: {100 * frac:.1f} % of the grid), "
                         f"rated {rated:g} (dashed)", fontsize=8.5)
            ax.set_xlabel(f"hip pitch {HIP_PITCH.replace('_joint', '')} [deg]")
            ax.set_ylabel(f"knee {KNEE.replace('_joint', '')} [deg]")
        fig.suptitle(f"HOAP-3 standing on the right sole: gravity torques of the stance leg over hip pitch × knee "
                     f"({args.n}×{args.n} poses, other joints at 0; one spatial.gravity batch call, "
                     f"{batch_s * 1e3:.2f} ms)", fontsize=10)
        fig.tight_layout()
        path = os.path.join(args.out, "torque_map.png")
        fig.savefig(path, dpi=110)
        plt.close(fig)
        summary["plot"] = os.path.basename(path)

    with open(os.path.join(args.out, "torque_map.json"), "w") as f:
        json.dump(summary, f, indent=1)

    def pct(x):
        return "–" if x is None else f"{100 * x:.1f} %"

    for rec in joints:
        at = rec["max_abs_tau_at"]
        print(f"{rec['joint']} ({rec['title']}): max |tau| {rec['max_abs_tau_Nm']:.3f} N m at hip pitch "
              f"{np.degrees(at['hip_pitch_rad']):.1f} deg, knee {np.degrees(at['knee_rad']):.1f} deg; limit "
              f"{rec['effort_limit_Nm']:g} N m, beyond it on {pct(rec['fraction_beyond_limit'])} of the grid "
              f"(beyond the rated {rec['rated_Nm']:g} N m: {pct(rec['fraction_beyond_rated'])})")
    print(f"python_torque_map.py: {H.size} poses in one spatial.gravity call ({batch_s * 1e3:.2f} ms); wrote "
          f"{os.path.join(args.out, 'torque_map.json')}" + (f" and {summary['plot']}" if summary["plot"] else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
