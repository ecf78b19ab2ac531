#!/usr/bin/env python3
"""Turns the stress suite's measurements into docs/stress.md and docs/stress_*.png.

    SPATIAL_STRESS_LONG=1 SPATIAL_STRESS_OUT=build/stress_long.csv build/bin/spatial_stress_tests
    build/venv/bin/python tools/stress_report.py build/stress_long.csv --out docs

The CSV (written by tests/stress_numerics.cpp) has one row per measurement: group, case, n, kappa, quantity,
scalar, value, bound, asserted. The table gives, per group, case and quantity, the worst value seen, its bound at
that sample and the worst ratio value / bound over the asserted samples. Charts need matplotlib; without it they
are skipped with a message.
"""

import argparse
import csv
import math
import os
import sys
from collections import OrderedDict


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r["n"] = int(r["n"])
        r["kappa"] = float(r["kappa"])
        r["value"] = float(r["value"])
        r["bound"] = float(r["bound"])
        r["asserted"] = r["asserted"] == "1"
    return rows


def fmt(x):
    if x is None:
        return "–"
    if isinstance(x, float) and (math.isinf(x) or math.isnan(x)):
        return str(x)
    if x == 0:
        return "0"
    return f"{x:.2e}"


def summarise(rows):
    groups = OrderedDict()
    for r in rows:
        key = (r["group"], r["case"], r["quantity"], r["scalar"])
        g = groups.setdefault(key, {"rows": []})
        g["rows"].append(r)
    out = []
    for (group, case, quantity, scalar), g in groups.items():
        rs = g["rows"]
        worst = max(rs, key=lambda r: (r["value"] if not math.isnan(r["value"]) else math.inf))
        asserted = [r for r in rs if r["asserted"]]
        ratio = None
        if asserted:
            ratio = max((r["value"] / r["bound"]) if r["bound"] > 0 else (0.0 if r["value"] == 0 else math.inf)
                        for r in asserted)
        out.append({
            "group": group, "case": case, "quantity": quantity, "scalar": scalar,
            "worst": worst["value"], "bound": worst["bound"], "n": worst["n"], "kappa": worst["kappa"],
            "samples": len(rs), "asserted": len(asserted), "ratio": ratio,
        })
    return out


def charts(rows, outdir):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("stress_report.py: matplotlib not available, charts skipped (bash scripts/peers.sh --no-pinocchio)")
        return []
    made = []
    # Error against n (growth group).
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    for ax, scalar in zip(axes, ("double", "float")):
        for case, marker in (("chain", "o"), ("tree", "s")):
            for quantity, color in (("FD error ABA", "C0"), ("FD error CRBA+LTDL", "C1"), ("RNEA error", "C2"),
                                    ("residual RNEA(ABA)", "C3")):
                pts = [(r["n"], r["value"]) for r in rows if r["group"] == "growth" and r["case"] == case
                       and r["quantity"] == quantity and r["scalar"] == scalar and r["value"] > 0]
                if pts:
                    ax.scatter(*zip(*pts), marker=marker, color=color, s=14, alpha=0.7,
                               label=f"{quantity}, {case}")
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel("bodies n")
        ax.set_ylabel("relative error")
        ax.set_title(f"Error against n ({scalar})")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(outdir, "stress_error_vs_n.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    made.append(path)

    # Condition number against n.
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for case, marker in (("chain", "o"), ("tree", "s")):
        pts = sorted({(r["n"], r["kappa"]) for r in rows if r["group"] == "growth" and r["case"] == case})
        if pts:
            ax.scatter(*zip(*pts), marker=marker, s=14, label=case)
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("bodies n")
    ax.set_ylabel("κ(H)")
    ax.set_title("Condition number of H on random trees")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    path = os.path.join(outdir, "stress_kappa_vs_n.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    made.append(path)

    # Forward-dynamics error against κ(H), every case, with the line n ε κ for n = 1.
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    for ax, scalar, eps in zip(axes, ("double", "float"), (2.0 ** -53, 2.0 ** -24)):
        for i, group in enumerate(("growth", "extreme", "speed", "hoap3")):
            pts = [(r["kappa"], r["value"]) for r in rows if r["group"] == group
                   and r["quantity"] == "FD error ABA" and r["scalar"] == scalar and r["value"] > 0]
            if pts:
                ax.scatter(*zip(*pts), s=12, alpha=0.7, color=f"C{i}", label=f"ABA, {group}")
            pts = [(r["kappa"], r["value"]) for r in rows if r["group"] == group
                   and r["quantity"] == "FD error CRBA+LTDL" and r["scalar"] == scalar and r["value"] > 0]
            if pts:
                ax.scatter(*zip(*pts), s=12, alpha=0.7, color=f"C{i}", marker="x", label=f"CRBA+LTDL, {group}")
        ks = [r["kappa"] for r in rows if r["kappa"] > 0]
        if ks:
            lo, hi = min(ks), max(ks)
            ax.plot([lo, hi], [eps * lo, eps * hi], "k--", lw=1, label="u κ(H)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("κ(H)")
        ax.set_ylabel("relative error of q̈")
        ax.set_title(f"Forward dynamics error against κ(H) ({scalar})")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(outdir, "stress_error_vs_kappa.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    made.append(path)
    return made


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--out", default="docs")
    ap.add_argument("--command", default="SPATIAL_STRESS_LONG=1 SPATIAL_STRESS_OUT=build/stress_long.csv "
                    "build/bin/spatial_stress_tests")
    args = ap.parse_args()
    rows = load(args.csv)
    os.makedirs(args.out, exist_ok=True)
    table = summarise(rows)
    pngs = charts(rows, args.out)

    lines = []
    lines.append("# Numerical stress: measured accuracy and its bounds")
    lines.append("")
    lines.append(f"Generated by `tools/stress_report.py` from the long form of the stress suite (raw: `stress_long.csv`) "
                 f"(`{args.command}`; {len(rows)} measurements). Every number below was measured by that run. The "
                 "bounds and why they have that form are in the comment at the top of `tests/stress_numerics.cpp`; "
                 "the constant is c = 16 throughout, u = 2⁻⁵³ (double), 2⁻²⁴ (float), ε_ld = 2⁻⁶⁴ (reference).")
    lines.append("")
    lines.append("Columns: *worst* is the largest value seen over the samples of that case, *bound* the bound at "
                 "that sample, *n* and *κ(H)* that sample's size and condition number, *worst/bound* the largest "
                 "ratio over the samples where the bound is asserted (c n u κ < 1; energy: where the step resolves "
                 "the motion), *asserted* how many of the samples were asserted.")
    lines.append("")
    current = None
    for t in table:
        if t["group"] != current:
            current = t["group"]
            lines.append("")
            lines.append(f"## {current}")
            lines.append("")
            lines.append("| case | quantity | scalar | n | κ(H) | worst | bound | worst/bound | asserted |")
            lines.append("|---|---|---|---|---|---|---|---|---|")
        lines.append(f"| {t['case']} | {t['quantity']} | {t['scalar']} | {t['n']} | {fmt(t['kappa'])} | "
                     f"{fmt(t['worst'])} | {fmt(t['bound'])} | {fmt(t['ratio'])} | {t['asserted']}/{t['samples']} |")
    lines.append("")
    if pngs:
        lines.append("## Charts")
        lines.append("")
        for p in pngs:
            name = os.path.basename(p)
            lines.append(f"![{name}]({name})")
            lines.append("")
    path = os.path.join(args.out, "stress.md")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"stress_report.py: wrote {path}" + (f" and {len(pngs)} charts" if pngs else ""))


if __name__ == "__main__":
    sys.exit(main())
