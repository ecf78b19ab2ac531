#!/usr/bin/env python3
"""The benchmark report: reads Google Benchmark JSON files and the error study's JSON, writes report.md,
summary.json and PNG charts, and prints the headline table.

Input layout (scripts/main.sh writes it):
    <input>/<compiler>/bench_*.json       Google Benchmark output, one file per binary (any name ending in .json
                                          other than error_study.json)
    <input>/<compiler>/error_study.json   bench/error_study.cpp output
<compiler> is a directory name (main.sh uses "gcc" and "clang"); every compiler becomes a column.

Benchmark names are "<impl>/<algorithm>/<model>/<scalar>/<tree>" (bench/bench_models.hpp). The time of a benchmark
is the median over repetitions (aggregate "median"; the single run when there are no repetitions) of the CPU time
per iteration (--time real: wall time). CPU time is the default because the machine may be shared: a preempted
process accumulates wall time but not CPU time.

Charts need matplotlib (scripts/peers.sh installs it into build/venv); without it the tables are still written.
The "Scenes" section reads <output>/scenes/*.json (spatial-dyn scene all; plots by tools/plot_scenes.py); the
"Walking (closed loop)" section reads <output>/walk*/walk.json (spatial-dyn walk; plots by tools/plot_walk.py) and adds
a record of kind "walking" to summary.json. The "Python package (issue 14)" section reads <output>/python/
(bench/python_bench.py's bench.md, tools/python_torque_map.py's torque_map.json and torque_map.png).
Usage: tools/report.py [--input build/report/raw] [--output build/report] [--time cpu|real] [--scenes DIR]
"""

import argparse
import datetime
import json
import math
import os
import platform
import re
import subprocess
import sys

CONTROL_PERIOD_NS = 2e6  # the 2 ms control period

# The reference study's MATLAB times, quoted in issue 4 (fixed rows, not measured here).
MATLAB_ROWS = [
    ("21-DoF RNEA", "stance21", "RNEA", 3e6),
    ("21-DoF CRBA", "stance21", "CRBA", 3e6),
    ("2-DoF RNEA", "pendulum2", "RNEA", 0.3e6),
]

# Fastest peer builds measured on this kind of machine for a 21-joint humanoid, quoted in issue 4 for orientation
# (not measured here): "our aim is to beat every one of them".
ORIENTATION_ROWS = [
    ("Pinocchio, clang", "RNEA", 2000.0),
    ("Pinocchio, clang", "CRBA", 1800.0),
    ("Pinocchio, clang", "ABA", 4300.0),
    ("Pinocchio, clang", "sparse LTDL", 800.0),
    ("Pinocchio CppADCodeGen", "RNEA", 1200.0),
    ("Pinocchio CppADCodeGen", "ABA", 3650.0),
    ("RBDL", "RNEA", 1700.0),
]

# Performance targets of issue 4: on the 21-DoF stance model in double, median ratio of spatial (compile-time tree)
# to the peer's call, measured in the same run with the same compiler and flags.
TARGET_MODEL = "stance21"
TARGETS = [
    ("RNEA vs Pinocchio rnea", "RNEA", "pinocchio", "RNEA", 0.4),
    ("gravity torques vs Pinocchio computeGeneralizedGravity", "GravityTorques", "pinocchio", "GravityTorques", 0.3),
    ("CRBA vs Pinocchio crba", "CRBA", "pinocchio", "CRBA", 0.55),
    ("ABA vs Pinocchio aba", "ABA", "pinocchio", "ABA", 0.45),
    ("FD by CRBA + LTDL vs Pinocchio crba + nonLinearEffects + cholesky", "FD_CRBA_LTDL", "pinocchio",
     "FD_CRBA_LTDL", 0.5),
    ("RNEA vs KDL TreeIdSolver_RNE", "RNEA", "kdl", "RNEA", 0.1),
]

# Performance targets of issue 11 (floating base): on floating27 (the HOAP-3 free-flying at the pelvis, nv = 27) in
# double, spatial's compile-time tree against Pinocchio's free-flyer model of the same robot, same compiler and run.
FLOATING_MODEL = "floating27"
GENERAL_MODEL = "ball38"  # bench_general: spherical joints (general.hpp)
FLOATING_TARGETS = [
    ("floating RNEA vs Pinocchio rnea", "RNEA", "pinocchio", "RNEA", 0.5),
    ("floating CRBA vs Pinocchio crba", "CRBA", "pinocchio", "CRBA", 0.5),
    ("floating ABA vs Pinocchio aba", "ABA", "pinocchio", "ABA", 0.5),
    ("all joint Jacobians vs Pinocchio computeJointJacobians", "JointJacobians", "pinocchio", "JointJacobians", 0.5),
    ("one frame Jacobian after them vs Pinocchio getFrameJacobian", "FrameJacobian", "pinocchio", "FrameJacobian", 0.5),
    ("one frame Jacobian in one call vs Pinocchio computeFrameJacobian", "ComputeFrameJacobian", "pinocchio",
     "ComputeFrameJacobian", 0.5),
    ("CoM Jacobian vs Pinocchio jacobianCenterOfMass", "ComJacobian", "pinocchio", "ComJacobian", 0.5),
    ("centroidal momentum matrix vs Pinocchio ccrba", "CentroidalMatrix", "pinocchio", "CentroidalMatrix", 0.5),
]

# Performance targets of issue 13 (analytical derivatives), on stance21 and floating27, double, compile-time trees.
DERIVATIVE_TARGETS = [
    ("RNEA derivatives vs Pinocchio computeRNEADerivatives", "RNEA_derivatives", "pinocchio", "RNEA_derivatives", 0.4),
    ("ABA derivatives vs Pinocchio computeABADerivatives", "ABA_derivatives", "pinocchio", "ABA_derivatives", 0.4),
    ("H⁻¹ vs Pinocchio computeMinverse", "Minv", "pinocchio", "Minv", 0.5),
]

# Why a target can be missed on this kind of machine and what would close it (analysis in docs/performance.md);
# printed under the targets table for the targets the run missed.
MISS_NOTES = {
    ("ABA", "clang"): "the AVX2 kernel's articulated-inertia pass (the rotation of the three 3×3 blocks into the "
                      "parent, 18 matrix–vector products per body) is the bulk; packing the symmetric blocks A and C "
                      "(6 entries each) or transforming them as 6×6 with AVX-512 would take a third of it off.",
    ("CRBA", None): "perf puts the AVX2 kernel's time in the lane broadcasts and FMAs of its 3×3 products and in the "
            "146 entries H_ij = S⁰ⱼ · F⁰ (horizontal sums and stores to both triangles, ~15 % together); summing the "
            "entries four at a time took 3 % of the instructions and no time off, nor did broadcasting from memory "
            "(scripts/ab.sh, docs/performance.md, 2026-12-07). Untried: writing one triangle of H.",
}

ALGORITHMS = ["RNEA", "GravityTorques", "BiasForces", "CRBA", "FD_CRBA_LTDL", "FD_CRBA_DenseLLT", "ABA", "FK", "LTDL",
              "JointJacobians", "FrameJacobian", "ComputeFrameJacobian", "ComJacobian", "CentroidalMatrix",
              "RNEA_derivatives", "ABA_derivatives", "RNEA_derivatives_fd", "Minv", "RNEA_derivatives_central",
              "RNEA_derivatives_ad", "ContactDynamics_6D", "ContactDynamics_2x6D", "ImpulseDynamics_2x6D", "WalkTick"]
ALGORITHM_TITLES = {
    "RNEA": "RNEA (inverse dynamics)",
    "GravityTorques": "gravity torques",
    "BiasForces": "bias forces C(q, q̇)",
    "CRBA": "CRBA (joint-space inertia)",
    "FD_CRBA_LTDL": "forward dynamics: CRBA + tree LTDL",
    "FD_CRBA_DenseLLT": "forward dynamics: CRBA + dense Cholesky",
    "ABA": "forward dynamics: ABA",
    "FK": "forward kinematics",
    "LTDL": "LTDL factorise + solve",
    "RNEA_derivatives": "∂τ/∂q, ∂τ/∂q̇ (analytical)",
    "ABA_derivatives": "∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ (analytical)",
    "RNEA_derivatives_fd": "∂τ/∂q, ∂τ/∂q̇ by forward differences (2n + 1 RNEA)",
    "RNEA_derivatives_central": "∂τ/∂q, ∂τ/∂q̇ by central differences (4n RNEA)",
    "RNEA_derivatives_ad": "∂τ/∂q, ∂τ/∂q̇ by forward-mode automatic differentiation",
    "Minv": "H⁻¹ directly (ABA-based, no H)",
    "ContactDynamics_6D": "constrained forward dynamics, one sole welded",
    "ContactDynamics_2x6D": "constrained forward dynamics, both soles welded",
    "ImpulseDynamics_2x6D": "impulse dynamics, both soles (inelastic)",
    "WalkTick": "one 2 ms tick of the whole-body walking generator",
}
PEER_CALLS = {
    ("kdl", "RNEA"): "TreeIdSolver_RNE",
    ("kdl", "CRBA"): "ChainDynParam::JntToMass",
    ("kdl", "FD_CRBA_LTDL"): "ChainFdSolver_RNE",
    ("pinocchio", "RNEA"): "rnea",
    ("pinocchio", "GravityTorques"): "computeGeneralizedGravity",
    ("pinocchio", "BiasForces"): "nonLinearEffects",
    ("pinocchio", "CRBA"): "crba (upper triangle)",
    ("pinocchio", "FD_CRBA_LTDL"): "crba + nonLinearEffects + cholesky",
    ("pinocchio", "ABA"): "aba",
    ("pinocchio", "FK"): "forwardKinematics",
    ("pinocchio", "RNEA_derivatives"): "computeRNEADerivatives",
    ("pinocchio", "ABA_derivatives"): "computeABADerivatives",
    ("pinocchio", "Minv"): "computeMinverse",
    ("pinocchio", "ContactDynamics_6D"): "constraintDynamics",
    ("pinocchio", "ContactDynamics_2x6D"): "constraintDynamics",
    ("pinocchio", "ImpulseDynamics_2x6D"): "impulseDynamics",
}
GROWTH_RE = re.compile(r"^(chain|binary)(\d+)$")
# Variants that compute the same result compete on one Pareto front: the three forward dynamics, and the derivatives
# of RNEA (analytical, automatic differentiation, forward and central differences); every other algorithm competes
# only with itself in the other scalar type.
FORWARD_DYNAMICS = ("ABA", "FD_CRBA_LTDL", "FD_CRBA_DenseLLT")
RNEA_DERIVATIVES = ("RNEA_derivatives", "RNEA_derivatives_fd", "RNEA_derivatives_central", "RNEA_derivatives_ad")


def result_group(algorithm):
    if algorithm in FORWARD_DYNAMICS:
        return "forward dynamics"
    if algorithm in RNEA_DERIVATIVES:
        return "RNEA derivatives"
    return algorithm


# ---------------------------------------------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------------------------------------------
def to_ns(value, unit):
    return value * {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[unit]


BATCH_RE = re.compile(r"^batch:(\d+)$")
THREADS_RE = re.compile(r"^threads:(\d+)$")


def batch_key(parts):
    """(impl, algorithm, model, scalar, tree, batch, threads) of a batched benchmark's name
    "<impl>/<algorithm>_batch/<model>/<scalar>/<tree>/batch:<B>/threads:<T>[/process_time][/real_time]" (bench_batch,
    bench_pinocchio_batch.cpp), else None."""
    if len(parts) < 7 or not parts[1].endswith("_batch"):
        return None
    b, t = BATCH_RE.match(parts[5]), THREADS_RE.match(parts[6])
    if not b or not t:
        return None
    return tuple(parts[:5]) + (int(b.group(1)), int(t.group(1)))


def read_benchmark_files(paths, time_kind):
    """Returns (context, {(impl, algorithm, model, scalar, tree): ns}, {batch key: {"cpu": ns, "real": ns}}) with the
    times per call (per batch for the batched benchmarks, see batch_key) of one binary, from the JSON files of its
    runs (one for scripts/main.sh; one per run for tools/ratio_spread.py, which runs a binary several times). Each
    run gives a benchmark one sample (the median aggregate of its repetitions) or several (its single repetitions,
    when it reports no aggregates); a benchmark's time is the median of its samples over all runs (the upper one of
    an even count). The context is the first file's."""
    key_time = "cpu_time" if time_kind == "cpu" else "real_time"
    context = None
    samples, batch_samples = {}, {}
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        if context is None:
            context = data.get("context", {})
        medians, singles = {}, {}
        batch_medians, batch_singles = {}, {}
        for b in data.get("benchmarks", []):
            run_name = b.get("run_name", b["name"])
            parts = run_name.split("/")
            if len(parts) < 5:
                continue
            bkey = batch_key(parts)
            if bkey:
                unit = b.get("time_unit", "ns")
                both = {"cpu": to_ns(b["cpu_time"], unit), "real": to_ns(b["real_time"], unit)}
                if b.get("run_type") == "aggregate":
                    if b.get("aggregate_name") == "median":
                        batch_medians[bkey] = [both]
                else:
                    batch_singles.setdefault(bkey, []).append(both)
                continue
            key = tuple(parts[:5])
            ns = to_ns(b[key_time], b.get("time_unit", "ns"))
            if b.get("run_type") == "aggregate":
                if b.get("aggregate_name") == "median":
                    medians[key] = [ns]
            else:
                singles.setdefault(key, []).append(ns)
        for key, values in {**singles, **medians}.items():
            samples.setdefault(key, []).extend(values)
        for key, values in {**batch_singles, **batch_medians}.items():
            batch_samples.setdefault(key, []).extend(values)
    times = {key: sorted(values)[len(values) // 2] for key, values in samples.items()}
    batch_times = {key: {k: sorted(v[k] for v in values)[len(values) // 2] for k in ("cpu", "real")}
                   for key, values in batch_samples.items()}
    return context or {}, times, batch_times


def read_inputs(input_dir, time_kind):
    compilers = {}
    if not os.path.isdir(input_dir):
        sys.exit(f"report.py: no input directory {input_dir}")
    for compiler in sorted(os.listdir(input_dir)):
        cdir = os.path.join(input_dir, compiler)
        if not os.path.isdir(cdir):
            continue
        entry = {"times": {}, "batch_times": {}, "contexts": {}, "error": None}
        for name in sorted(os.listdir(cdir)):
            path = os.path.join(cdir, name)
            if not name.endswith(".json"):
                continue
            try:
                if name == "error_study.json":
                    with open(path) as f:
                        entry["error"] = json.load(f)
                else:
                    context, times, batch_times = read_benchmark_files([path], time_kind)
                    entry["contexts"][name[:-5]] = context
                    entry["times"].update(times)
                    entry["batch_times"].update(batch_times)
            except (OSError, ValueError, KeyError) as e:
                print(f"report.py: skipping {path}: {e}", file=sys.stderr)
        if entry["times"] or entry["batch_times"] or entry["error"]:
            compilers[compiler] = entry
    # gcc before clang, then the rest alphabetically
    order = {"gcc": 0, "clang": 1}
    return dict(sorted(compilers.items(), key=lambda kv: (order.get(kv[0], 2), kv[0])))


# ---------------------------------------------------------------------------------------------------------------
# Machine and build facts
# ---------------------------------------------------------------------------------------------------------------
def machine_info():
    info = {"model_name": platform.processor() or platform.machine(), "cpus": os.cpu_count(), "cores": None,
            "threads_per_core": None}
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        fields = {}
        for line in out.splitlines():
            if ":" in line:
                k, v = line.split(":", 1)
                fields[k.strip()] = v.strip()
        info["model_name"] = fields.get("Model name", info["model_name"])
        info["cpus"] = int(fields.get("CPU(s)", info["cpus"] or 0))
        cores_per_socket = int(fields.get("Core(s) per socket", 0))
        sockets = int(fields.get("Socket(s)", 1) or 1)
        info["cores"] = cores_per_socket * sockets if cores_per_socket else None
        info["threads_per_core"] = int(fields.get("Thread(s) per core", 0)) or None
        flags = fields.get("Flags", "").split()
        info["simd"] = [f for f in ("avx2", "fma", "avx512f") if f in flags]
    except (OSError, subprocess.CalledProcessError, ValueError):
        pass
    info["kernel"] = platform.release()
    return info


def first_context_value(entry, key):
    for context in entry["contexts"].values():
        if key in context:
            return context[key]
    return None


def context_value(entry, file_prefix, key):
    for name, context in entry["contexts"].items():
        if name.startswith(file_prefix) and key in context:
            return context[key]
    return None


# ---------------------------------------------------------------------------------------------------------------
# Formatting
# ---------------------------------------------------------------------------------------------------------------
def fmt_ns(ns):
    if ns is None:
        return "–"
    if ns >= 1e6:
        return f"{ns / 1e6:.3g} ms"
    if ns >= 1e3:
        return f"{ns / 1e3:.3g} µs"
    return f"{ns:.3g} ns"


def fmt_ratio(r, digits=3):
    if r is None:
        return "–"
    return f"{r:.{digits}g}"


def fmt_err(e):
    if e is None:
        return "–"
    return f"{e:.2e}"


def fmt_mm(metres):
    return f"{metres * 1e3:.1f}"


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    for r in rows:
        lines.append("| " + " | ".join(str(c) for c in r) + " |")
    return "\n".join(lines)


def text_table(header, rows):
    widths = [max(len(str(h)), *(len(str(r[i])) for r in rows)) if rows else len(str(h)) for i, h in enumerate(header)]
    out = ["  ".join(str(h).ljust(w) for h, w in zip(header, widths)),
           "  ".join("-" * w for w in widths)]
    for r in rows:
        out.append("  ".join(str(c).ljust(w) for c, w in zip(r, widths)))
    return "\n".join(out)


def ratio(a, b):
    if a is None or b is None or b == 0:
        return None
    return a / b


def pareto_front(points):
    """Indices of the points not dominated in (x, y), both minimised."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best_y = [], math.inf
    for i in order:
        if points[i][1] < best_y:
            front.append(i)
            best_y = points[i][1]
    return set(front)


def fit_exponent(ns_by_n):
    """Least-squares slope of log(time) against log(n)."""
    pts = [(math.log(n), math.log(t)) for n, t in ns_by_n if t and t > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    if sxx == 0:
        return None
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


# ---------------------------------------------------------------------------------------------------------------
# The report
# ---------------------------------------------------------------------------------------------------------------
def build(compilers, time_kind):
    """Summary records and derived tables."""
    records = []
    for compiler, entry in compilers.items():
        times = entry["times"]
        errors = {}
        if entry["error"]:
            for p in entry["error"].get("algorithms", []):
                errors[(p["model"], p["algorithm"], p["scalar"])] = (p.get("max_rel_error"), p.get("median_rel_error"))
        for (impl, algorithm, model, scalar, tree), ns in times.items():
            if impl != "spatial":
                continue
            kdl_ns = times.get(("kdl", algorithm, model, scalar, "-"))
            pin_ns = times.get(("pinocchio", algorithm, model, scalar, "-"))
            err = errors.get((model, algorithm, scalar), (None, None))
            growth = GROWTH_RE.match(model)
            records.append({
                "compiler": compiler,
                "model": model,
                "algorithm": algorithm,
                "scalar": scalar,
                "tree": tree,
                "ns": ns,
                "kdl_ns": kdl_ns,
                "pinocchio_ns": pin_ns,
                "ratio_to_control_period": ns / CONTROL_PERIOD_NS,
                "ratio_to_kdl": ratio(ns, kdl_ns),
                "ratio_to_pinocchio": ratio(ns, pin_ns),
                "max_rel_error": err[0],
                "median_rel_error": err[1],
                "kind": "growth" if growth else "model",
                "bodies": int(growth.group(2)) if growth else None,
                "time": time_kind,
            })
    return records


def build_batch(compilers, time_kind, records):
    """summary.json records of the batched benchmarks (issue 15), one per compiler, model, algorithm, scalar, tree,
    batch size and thread count: "ns" = time per state. On one thread the time is `time_kind`'s (CPU time by default);
    on several, wall time (the CPU time of one thread would miss the others' work, that of the process would not be a
    throughput). Scaling = wall time per state on one thread ÷ on T threads, same run."""
    out = []
    for compiler, entry in compilers.items():
        bt = entry.get("batch_times", {})
        errors = {}
        if entry["error"]:
            for p in entry["error"].get("algorithms", []):
                errors[(p["model"], p["algorithm"], p["scalar"])] = (p.get("max_rel_error"), p.get("median_rel_error"))

        def per_state(key):
            t = bt.get(key)
            if not t:
                return None, None, None
            b, threads = key[5], key[6]
            ns = (t[time_kind] if threads == 1 else t["real"]) / b
            return ns, t["real"] / b, t["cpu"] / b

        for key in bt:
            impl, algorithm, model, scalar, tree, b, threads = key
            if impl != "spatial":
                continue
            ns, wall, cpu = per_state(key)
            _, one_wall, one_cpu = per_state(key[:6] + (1,))
            pin_key = ("pinocchio", algorithm, model, scalar, "-", b, threads)
            pin_ns, pin_wall, _ = per_state(pin_key)
            pin_one_wall = per_state(pin_key[:6] + (1,))[1]
            base = algorithm[:-len("_batch")]
            # FK_batch places one frame by a walk over its chain (Batch::frame_placement); the single-state FK
            # record is the whole tree's forward kinematics: not the same work, so no single-state figure beside it.
            single = None if base == "FK" else find(records, compiler=compiler, model=model, algorithm=base,
                                                    scalar=scalar, tree=tree)
            err = errors.get((model, algorithm, scalar), (None, None))
            out.append({
                "compiler": compiler,
                "model": model,
                "algorithm": algorithm,
                "scalar": scalar,
                "tree": tree,
                "batch": b,
                "threads": threads,
                "ns": ns,
                "wall_ns": wall,
                "process_cpu_ns": cpu,
                "states_per_second": 1e9 / ns if ns else None,
                "states_per_second_per_core": 1e9 / ns / threads if ns else None,
                "scaling": ratio(one_wall, wall) if threads > 1 else None,
                # CPU time of the process ÷ wall time: the cores the run obtained (below `threads` when other
                # processes ran on the machine), and the scaling that the CPU work per state would give on
                # `threads` free cores (threads × CPU per state on one thread ÷ on `threads`)
                "cores_used": ratio(cpu, wall),
                "scaling_on_free_cores": threads * ratio(one_cpu, cpu) if threads > 1 and ratio(one_cpu, cpu)
                else None,
                "pinocchio_ns": pin_ns,
                "ratio_to_pinocchio": ratio(ns, pin_ns),
                "pinocchio_scaling": ratio(pin_one_wall, pin_wall) if threads > 1 else None,
                "single_state_ns": single["ns"] if single else None,
                "speedup_over_single_state": ratio(single["ns"] if single else None, ns),
                "max_rel_error": err[0],
                "median_rel_error": err[1],
                "kind": "batch",
                "time": time_kind if threads == 1 else "real",
            })
    out.sort(key=lambda r: (r["compiler"], r["model"] != TARGET_MODEL, r["model"],
                            algorithm_sort_key(r["algorithm"][:-len("_batch")]), r["scalar"] != "double",
                            r["tree"] != "static", r["batch"], r["threads"]))
    return out


# Targets of issue 15 on stance21, compile-time tree, B = BATCH_TARGET_B (inputs and outputs in cache): time per
# state on one thread, and the throughput's scaling on all cores (the machine's 2).
BATCH_TARGET_B = 1024
BATCH_TARGETS = [
    ("batched RNEA, double, one core", "RNEA_batch", "double", 200.0),
    ("batched RNEA, float, one core", "RNEA_batch", "float", 100.0),
    ("batched ABA, double, one core", "ABA_batch", "double", 500.0),
    ("batched CRBA, double, one core", "CRBA_batch", "double", 350.0),
]
BATCH_SCALING_TARGET = 1.8
BATCH_SCALING_ALGORITHMS = ("RNEA_batch", "CRBA_batch", "ABA_batch")


def batch_target_rows(batch_records, compilers):
    rows = []
    for title, algorithm, scalar, target in BATCH_TARGETS:
        for c in compilers:
            for b in sorted({r["batch"] for r in batch_records}):
                r = find(batch_records, compiler=c, model=TARGET_MODEL, algorithm=algorithm, scalar=scalar,
                         tree="static", batch=b, threads=1)
                if not r or r["ns"] is None:
                    continue
                ok = r["ns"] <= target
                gap = "–" if ok else f"{r['ns'] / target:.3g}× too slow: needs {(1 - target / r['ns']) * 100:.2g}% less time"
                rows.append([title, c, b, f"≤ {fmt_ns(target)}", fmt_ns(r["ns"]), "pass" if ok else "miss", gap])
    for algorithm in BATCH_SCALING_ALGORITHMS:
        for c in compilers:
            for b in sorted({r["batch"] for r in batch_records}):
                r = next((r for r in batch_records if r["compiler"] == c and r["model"] == TARGET_MODEL
                          and r["algorithm"] == algorithm and r["scalar"] == "double" and r["tree"] == "static"
                          and r["batch"] == b and r["threads"] > 1), None)
                if not r or r["scaling"] is None:
                    continue
                ok = r["scaling"] >= BATCH_SCALING_TARGET
                note = ""
                if not ok and r["cores_used"] is not None and r["cores_used"] < 0.9 * r["threads"]:
                    note = (f"; the run obtained {r['cores_used']:.2f} of {r['threads']} cores (other processes): "
                            f"{r['scaling_on_free_cores']:.2f}× on free cores by its CPU time per state"
                            if r["scaling_on_free_cores"] else "")
                rows.append([f"{algorithm.replace('_batch', '')} throughput on {r['threads']} threads ÷ on 1 (double)",
                             c, b, f"≥ {BATCH_SCALING_TARGET}×", f"{r['scaling']:.2f}×", "pass" if ok else "miss",
                             ("–" if ok else f"{BATCH_SCALING_TARGET / r['scaling']:.3g}× short") + note])
    return ["target", "compiler", "B", "target", "measured", "pass/miss", "gap"], rows


def batch_section(w, batch_records, compilers):
    """The batched algorithms of issue 15 (bench_batch, and Pinocchio's batch API from bench_pinocchio)."""
    if not batch_records:
        return
    w("## Batched algorithms (issue 15)")
    w("")
    w("`spatial::Batch` (include/spatial/batch.hpp): B states per call, each SIMD lane one state (xsimd; lanes per "
      "register in the machine table's build: see `spatial_batch_lanes_*` in bench_batch's JSON context), over its "
      "own worker pool. Time per state = time of one call ÷ B: on one thread the median CPU time, on several the "
      "median wall time (the run's throughput). Scaling = wall time per state on one thread ÷ on all threads, same "
      "run. bench_batch compares every batched result with the single-state call on the same state before timing "
      "(≤ 1e-12 relative in double, ≤ 1e-4 in float). Pinocchio: its batch API (`rneaInParallel`, `abaInParallel`: "
      "an OpenMP loop over its single-state calls, one model and data per thread; bench/bench_pinocchio_batch.cpp "
      "says how it is run; CRBA: the same loop over `crba`, Pinocchio having no batch call for it) on the same "
      "states and cores. Single state: bench_algorithms' time per call of the same algorithm, model, scalar and tree "
      "(none for FK_batch, one frame's placement by a walk over its chain, where the single-state FK is the whole "
      "tree's forward kinematics).")
    w("")
    header, rows = batch_target_rows(batch_records, compilers)
    w(f"Targets ({TARGET_MODEL}, compile-time tree; time per state on one thread, scaling on all threads; every "
      "B measured: 1024 keeps inputs and τ or q̈ in cache, 10000 does not; CRBA also at 128, where H of every "
      "state (nv × nv each) still fits in L2). Where the scaling falls short while the run obtained fewer cores "
      "than threads (process CPU time ÷ wall time), the gap column says so and what the CPU time per state "
      "implies on free cores: then the machine, not the algorithm, limited the run.")
    w("")
    w(md_table(header, rows))
    w("")
    rows = []
    for r in batch_records:
        single = r["single_state_ns"]
        rows.append([r["compiler"], r["model"], r["algorithm"], r["scalar"], r["tree"], r["batch"], r["threads"],
                     fmt_ns(r["ns"]), f"{r['states_per_second'] / 1e6:.3g} M" if r["states_per_second"] else "–",
                     f"{r['states_per_second_per_core'] / 1e6:.3g} M" if r["states_per_second_per_core"] else "–",
                     f"{r['scaling']:.2f}×" if r["scaling"] else "–",
                     f"{r['cores_used']:.2f}" if r["cores_used"] else "–", fmt_ns(r["pinocchio_ns"]),
                     fmt_ratio(r["ratio_to_pinocchio"]),
                     f"{r['pinocchio_scaling']:.2f}×" if r["pinocchio_scaling"] else "–", fmt_ns(single),
                     f"{r['speedup_over_single_state']:.2f}×" if r["speedup_over_single_state"] else "–"])
    w("Every batched benchmark (time per state; states per second in total and per core):")
    w("")
    w(md_table(["compiler", "model", "algorithm", "scalar", "tree", "B", "threads", "time per state", "states/s",
                "states/s per core", "scaling", "cores obtained", "Pinocchio per state", "÷ Pinocchio", "Pinocchio scaling",
                "single-state call", "single ÷ batched"], rows))
    w("")
    frows = []
    for r in batch_records:
        if r["scalar"] != "float" or r["threads"] != 1:
            continue
        d = find(batch_records, compiler=r["compiler"], model=r["model"], algorithm=r["algorithm"], scalar="double",
                 tree=r["tree"], batch=r["batch"], threads=r["threads"])
        if d and d["ns"] and r["ns"]:
            frows.append([r["compiler"], r["model"], r["algorithm"], r["tree"], r["batch"], r["threads"],
                          f"{d['ns'] / r['ns']:.2f}×"])
    if frows:
        w("float against double on one thread (issue 15: ≈ 2×, twice the lanes): double's time per state ÷ "
          "float's.")
        w("")
        w(md_table(["compiler", "model", "algorithm", "tree", "B", "threads", "double ÷ float"], frows))
        w("")


def find(records, **kw):
    for r in records:
        if all(r.get(k) == v for k, v in kw.items()):
            return r
    return None


def model_names(records):
    names = []
    for r in records:
        if r["kind"] == "model" and r["model"] not in names:
            names.append(r["model"])
    return names


def algorithm_sort_key(a):
    return ALGORITHMS.index(a) if a in ALGORITHMS else len(ALGORITHMS)


def headline_rows(records, compilers):
    rows = []
    algorithms = sorted({r["algorithm"] for r in records if r["model"] == TARGET_MODEL}, key=algorithm_sort_key)
    for algorithm in algorithms:
        row = [ALGORITHM_TITLES.get(algorithm, algorithm)]
        for c in compilers:
            r = find(records, compiler=c, model=TARGET_MODEL, algorithm=algorithm, scalar="double", tree="static")
            row.append(fmt_ns(r["ns"] if r else None))
        for c in compilers:
            r = find(records, compiler=c, model=TARGET_MODEL, algorithm=algorithm, scalar="double", tree="static")
            row.append(fmt_ratio(r["ratio_to_pinocchio"] if r else None))
        for c in compilers:
            r = find(records, compiler=c, model=TARGET_MODEL, algorithm=algorithm, scalar="double", tree="static")
            row.append(fmt_ratio(r["ratio_to_kdl"] if r else None))
        r = find(records, model=TARGET_MODEL, algorithm=algorithm, scalar="double", tree="static")
        row.append(f"{r['ratio_to_control_period']:.1e}" if r else "–")
        row.append(fmt_err(r["max_rel_error"] if r else None))
        rows.append(row)
    header = ["algorithm"] + [f"time {c}" for c in compilers] + [f"÷ Pinocchio {c}" for c in compilers] + \
             [f"÷ KDL {c}" for c in compilers] + ["÷ 2 ms", "max rel. error"]
    return header, rows


def target_rows(records, compilers, have_pinocchio, targets=None, model=None):
    targets = TARGETS if targets is None else targets
    model = TARGET_MODEL if model is None else model
    rows = []
    for title, algorithm, peer, peer_algorithm, target in targets:
        for c in compilers:
            r = find(records, compiler=c, model=model, algorithm=algorithm, scalar="double", tree="static")
            peer_ns = None
            if r:
                peer_ns = r["pinocchio_ns"] if peer == "pinocchio" else r["kdl_ns"]
            measured = ratio(r["ns"] if r else None, peer_ns)
            if measured is None:
                verdict = "absent" if peer == "pinocchio" and not have_pinocchio.get(c) else "not measured"
                rows.append([title, c, f"≤ {target}", "–", verdict, "–"])
                continue
            ok = measured <= target
            gap = "" if ok else f"{measured / target:.4g}× too slow: needs {(1 - target / measured) * 100:.2g}% less time"
            rows.append([title, c, f"≤ {target}", f"{measured:.3f}", "pass" if ok else "miss", gap or "–"])
    return ["target", "compiler", "target ratio", "measured ratio", "pass/miss", "gap"], rows


def write_charts(out_dir, records, compilers, notes, batch_records=()):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        notes.append("matplotlib is not installed: no charts (run scripts/peers.sh).")
        return []
    charts = []

    # 1. time per algorithm and model, double, compile-time tree, with the 2 ms line
    models = model_names(records)
    algorithms = [a for a in ALGORITHMS if any(r["algorithm"] == a and r["kind"] == "model" for r in records)]
    fig, axes = plt.subplots(1, max(1, len(models)), figsize=(5.5 * max(1, len(models)), 5), squeeze=False)
    series = [(c, "spatial") for c in compilers] + [(c, "pinocchio") for c in compilers] + [(c, "kdl") for c in compilers]
    for ax, model in zip(axes[0], models):
        width = 0.8 / len(series)
        plotted = False
        for s_i, (c, impl) in enumerate(series):
            xs, ys = [], []
            for a_i, a in enumerate(algorithms):
                r = find(records, compiler=c, model=model, algorithm=a, scalar="double", tree="static")
                if not r:
                    continue
                v = r["ns"] if impl == "spatial" else (r["pinocchio_ns"] if impl == "pinocchio" else r["kdl_ns"])
                if v:
                    xs.append(a_i + (s_i - len(series) / 2 + 0.5) * width)
                    ys.append(v)
            if xs:
                ax.bar(xs, ys, width=width, label=f"{impl} ({c})")
                plotted = True
        ax.axhline(CONTROL_PERIOD_NS, color="red", linestyle="--", label="2 ms control period")
        ax.set_yscale("log")
        ax.set_xticks(range(len(algorithms)))
        ax.set_xticklabels(algorithms, rotation=45, ha="right", fontsize=8)
        ax.set_title(f"{model} (double)")
        ax.set_ylabel("time per call [ns]")
        if plotted:
            ax.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(out_dir, "time_per_algorithm.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    charts.append(("Time per call, per algorithm and model (double, compile-time tree), with the 2 ms line",
                   os.path.basename(path)))

    # 2. run time against error, with the Pareto front
    fig, axes = plt.subplots(3, max(1, len(compilers)), figsize=(6.5 * max(1, len(compilers)), 15), squeeze=False)
    for col, c in enumerate(compilers):
        ax = axes[2][col]
        step = step_points(compilers[c])
        if step:
            front = pareto_front([(p["ns"], p["max_rel_error"]) for p in step])
            for i, p in enumerate(step):
                ax.scatter([p["ns"]], [p["max_rel_error"]], marker="o" if p["scalar"] == "double" else "^",
                           color="tab:purple" if p["dof"] == 2 else ("tab:blue" if p["dof"] == 21 else "tab:cyan"),
                           zorder=3)
                ax.annotate(f"{p['variant']} ({p['dof']} DoF, {p['scalar']})", (p["ns"], p["max_rel_error"]),
                            fontsize=6, xytext=(3, 3), textcoords="offset points")
            fp = sorted((step[i]["ns"], step[i]["max_rel_error"]) for i in front)
            ax.step([p[0] for p in fp], [p[1] for p in fp], where="post", color="green", label="Pareto front")
            ax.scatter([p[0] for p in fp], [p[1] for p in fp], s=90, facecolors="none", edgecolors="green", zorder=4)
            ax.legend(fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("median time per call of the resultant force (RNEA + ground wrench) [ns]")
        ax.set_ylabel("max relative error of the resultant force")
        ax.set_title(f"step: resultant force, full vs reduced vs pendulum ({c})", fontsize=9)
    for col, c in enumerate(compilers):
        pts = variant_points(records, c, batch_records)
        ax = axes[0][col]
        if pts:
            front = grouped_pareto(pts)
            for i, (x, y, label, scalar, group) in enumerate(pts):
                batched = "_batch" in label
                ax.scatter([x], [y], marker=("s" if scalar == "double" else "D") if batched else
                           ("o" if scalar == "double" else "^"),
                           color="tab:red" if group == "forward dynamics" else
                           ("tab:blue" if scalar == "double" else "tab:orange"), zorder=3)
                ax.annotate(label, (x, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
            fd = sorted((pts[i][0], pts[i][1]) for i in front if pts[i][4] == "forward dynamics")
            if fd:
                ax.step([p[0] for p in fd], [p[1] for p in fd], where="post", color="green",
                        label="Pareto front of forward dynamics")
            fp = [(pts[i][0], pts[i][1]) for i in front]
            ax.scatter([p[0] for p in fp], [p[1] for p in fp], s=90, facecolors="none", edgecolors="green", zorder=4,
                       label="on the Pareto front of its result")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("median time per call [ns]")
        ax.set_ylabel("max relative error vs long double")
        ax.set_title(f"{TARGET_MODEL}: variants ({c}; ○ double, △ float, □ ◇ batched, per state; red: FD)",
                     fontsize=9)
        ax.legend(fontsize=7)
        ax = axes[1][col]
        sim = simulation_points(compilers[c])
        if sim:
            front = pareto_front([(p["ns_per_simulated_second"], p["max_abs_error_q"]) for p in sim])
            methods = sorted({p["method"] for p in sim})
            for m_i, m in enumerate(methods):
                sel = [p for p in sim if p["method"] == m]
                ax.plot([p["ns_per_simulated_second"] for p in sel], [p["max_abs_error_q"] for p in sel], marker="o",
                        label=m)
                for p in sel:
                    ax.annotate(f"{p['dt']:g}", (p["ns_per_simulated_second"], p["max_abs_error_q"]), fontsize=6,
                                xytext=(3, 3), textcoords="offset points")
            fp = sorted((sim[i]["ns_per_simulated_second"], sim[i]["max_abs_error_q"]) for i in front)
            ax.step([p[0] for p in fp], [p[1] for p in fp], where="post", color="green", linestyle=":",
                    label="Pareto front")
            ax.scatter([p[0] for p in fp], [p[1] for p in fp], s=90, facecolors="none", edgecolors="green", zorder=4)
            ax.axvline(1e9, color="red", linestyle="--", label="real time (1 s per s)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("CPU time per simulated second [ns]")
        ax.set_ylabel("max |q − q_ref| after 1 s [rad]")
        ax.set_title(f"integrators on {TARGET_MODEL} ({c}; labels: step [s])")
        ax.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(out_dir, "runtime_vs_error.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    charts.append(("Run time against error, Pareto front in green", os.path.basename(path)))

    # 3. cost growth, log-log
    growth = [r for r in records if r["kind"] == "growth"]
    growth_compilers = [c for c in compilers if growth_series(growth, c)]  # main.sh: the first compiler only
    if growth_compilers:
        fig, axes = plt.subplots(1, len(growth_compilers), figsize=(7 * len(growth_compilers), 5.5), squeeze=False)
        for col, c in enumerate(growth_compilers):
            ax = axes[0][col]
            for key, pts in growth_series(growth, c).items():
                algorithm, shape, tree = key
                k = fit_exponent(pts)
                ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o" if tree == "runtime" else "s",
                        linestyle="-" if shape == "chain" else "--",
                        label=f"{algorithm} {shape} {tree} (k={k:.2f})" if k is not None else f"{algorithm} {shape}")
            ax.set_xscale("log", base=2)
            ax.set_yscale("log")
            ax.set_xlabel("bodies n")
            ax.set_ylabel("time per call [ns]")
            ax.set_title(f"cost growth ({c}); solid: chains, dashed: binary trees")
            ax.legend(fontsize=6, ncol=2)
        fig.tight_layout()
        path = os.path.join(out_dir, "cost_growth.png")
        fig.savefig(path, dpi=110)
        plt.close(fig)
        charts.append(("Cost growth, log–log, with the fitted exponent k of time ∝ n^k", os.path.basename(path)))
    return charts


def variant_points(records, compiler, batch_records=()):
    """(time, error, label, scalar, group) for every algorithm variant of the target model that has both; with
    batch_records, also the batched variants (time per state on one thread at B = BATCH_TARGET_B, compile-time tree;
    error of the batched call, error study), competing with the single-state calls of the same result."""
    pts = []
    for r in batch_records:
        if (r["compiler"] == compiler and r["model"] == TARGET_MODEL and r["tree"] == "static" and r["threads"] == 1
                and r["batch"] == BATCH_TARGET_B and r["ns"] and r["max_rel_error"]):
            pts.append((r["ns"], r["max_rel_error"], f"{r['algorithm']} {r['scalar']} (per state)", r["scalar"],
                        result_group(r["algorithm"][:-len("_batch")])))
    for r in records:
        # The AD derivatives run on the run-time twin in dual numbers (there is no compile-time tree in duals).
        if (r["compiler"] == compiler and r["model"] == TARGET_MODEL
                and (r["tree"] == "static" or r["algorithm"] == "RNEA_derivatives_ad")
                and r["ns"] and r["max_rel_error"]):
            pts.append((r["ns"], r["max_rel_error"], f"{r['algorithm']} {r['scalar']}", r["scalar"],
                        result_group(r["algorithm"])))
    return pts


def grouped_pareto(pts):
    """Indices on the Pareto front of their result group (variants computing the same result)."""
    front = set()
    for group in {p[4] for p in pts}:
        idx = [i for i, p in enumerate(pts) if p[4] == group]
        front |= {idx[j] for j in pareto_front([(pts[i][0], pts[i][1]) for i in idx])}
    return front


def step_points(entry):
    """The stepping scene's variants (bench/error_study_scenes.hpp), with a time and a nonzero error."""
    if not entry.get("error"):
        return []
    return [p for p in (entry["error"].get("step_resultant") or {}).get("points", [])
            if p.get("ns") and p.get("max_rel_error")]


def simulation_points(entry):
    if not entry.get("error"):
        return []
    return [p for p in entry["error"].get("simulation", {}).get("points", [])
            if p.get("ns_per_simulated_second") and p.get("max_abs_error_q")]


def growth_series(growth, compiler):
    series = {}
    for r in growth:
        if r["compiler"] != compiler:
            continue
        shape = GROWTH_RE.match(r["model"]).group(1)
        series.setdefault((r["algorithm"], shape, r["tree"]), []).append((r["bodies"], r["ns"]))
    return {k: sorted(v) for k, v in sorted(series.items(), key=lambda kv: (algorithm_sort_key(kv[0][0]), kv[0][1:]))}


def savings_rows(compilers):
    """Scene options (bench/bench_scenes.cpp, "scene/<ALG>.<Variant>/<model>/<scalar>/<tree>") against
    "<ALG>.Full" of the same model, scalar and tree: one row per option and compiler."""
    rows = []
    for c, entry in compilers.items():
        times = {k: v for k, v in entry["times"].items() if k[0] == "scene"}
        for (impl, algorithm, model, scalar, tree), ns in sorted(times.items()):
            if "." not in algorithm:
                continue
            base, variant = algorithm.split(".", 1)
            if variant == "Full":
                continue
            full = times.get((impl, f"{base}.Full", model, scalar, tree))
            if not full:
                continue
            rows.append([c, base, variant, model, tree, fmt_ns(ns), fmt_ns(full), fmt_ratio(ns / full),
                         f"{100.0 * (1.0 - ns / full):.0f} %"])
    return rows


def scenes_section(w, scenes_dir, out_dir):
    """The reference study's scenes (`spatial-dyn scene all`, tools/plot_scenes.py): a table of each scene's maxima
    and time per sample, the comparison with the study, links to the plots."""
    names = ["torso_arms", "torso_strokes", "circles", "step", "pendulum"]
    summaries = {}
    for n in names:
        path = os.path.join(scenes_dir, n + ".json")
        if os.path.exists(path):
            try:
                with open(path) as f:
                    summaries[n] = json.load(f)
            except (OSError, ValueError) as e:
                print(f"report.py: skipping {path}: {e}", file=sys.stderr)
    w("## Scenes: the reference study's experiments")
    w("")
    if not summaries:
        w(f"No scene output in `{scenes_dir}` (run `build/bin/spatial-dyn scene all --out {scenes_dir}`).")
        w("")
        return
    rel = os.path.relpath(scenes_dir, out_dir)
    w("`spatial-dyn scene all` (README, \"The reference study's scenes\"): cubic joint trajectories sampled at 2 ms, "
      "torques by RNEA, accelerations recomputed by forward dynamics (CRBA + LTDL, ABA) from those torques. Time per "
      "sample = median over the samples of RNEA + FD (CRBA) + FD (ABA), compile-time tree, double, wall time "
      "(steady_clock) on this shared machine. Via points and durations are ours where the study gives none (each "
      "scene's JSON lists them).")
    w("")
    rows = []
    for n, sm in summaries.items():
        tr, tm = sm["max_tau_over_rated"], sm["max_tau_over_max"]
        timing = sm["timing"]
        plots = [f"[{p}]({rel}/{p})" for p in (n + ".png", n + "_resultant.png")
                 if os.path.exists(os.path.join(scenes_dir, p))]
        rows.append([n, sm["model"], sm["samples"], f"{tr['value']:.3f} ({tr['joint'].replace('_joint', '')})",
                     f"{tm['value']:.3f}", fmt_err(sm["max_qdd_diff_crba"]["value"]),
                     fmt_err(sm["max_qdd_diff_aba"]["value"]), f"{sm['max_abs_qdd']:.3g}",
                     fmt_ns(timing["sample_ns"]), f"{timing['sample_ns'] / timing['period_ns']:.1e}",
                     ", ".join(plots) or "–"])
    w(md_table(["scene", "model", "samples", "max abs(τ)/rated", "max abs(τ)/max", "max abs(Δq̈) CRBA [rad/s²]",
                "max abs(Δq̈) ABA [rad/s²]", "max abs(q̈) [rad/s²]", "time per sample", "÷ 2 ms", "plots"], rows))
    w("")
    res = (summaries.get("pendulum") or summaries.get("step") or {}).get("resultant")
    if res:
        study = (summaries.get("pendulum") or summaries.get("step"))["study"]
        pend = res.get("pendulum_start_Fz_N")
        w("**The step against the study** (resultant force of the ground on the robot, sole frame, z up):")
        w("")
        rows = [["vertical force at the start, whole body", f"{study['Fz_start_whole_N']} N",
                 f"{res['start_F_N'][2]:.2f} N"],
                ["vertical force at the start, double pendulum", f"{study['Fz_start_pendulum_N']} N",
                 f"{pend:.2f} N" if pend is not None else "–"],
                ["static weight", f"{study['static_weight_N']} N (8.8 kg × 9.8)",
                 f"{res['weight_N']:.2f} N ({res['mass_kg']} kg × {res['g']}); static resultant "
                 f"{res['static_Fz_N']:.4f} N"],
                ["horizontal force at the start, whole body", f"Fy {study['Fy_start_whole_N']} N",
                 f"Fx {res['start_F_N'][0]:.2f} N, Fy {res['start_F_N'][1]:.2f} N"],
                ["ZMP in the sole (0.10 × 0.06 m, assumed)", "–",
                 f"{'always' if res['zmp_inside'] else 'NOT always'}; min margin {res['min_zmp_margin_m'] * 1e3:.1f} mm"]]
        w(md_table(["quantity", "study (quoted)", "this run"], rows))
        w("")
        w("The static weight differs by the mass table (8.8024 kg with the chest's CPU and wireless LAN, against the "
          "study's rounded 8.8 kg) and by g (9.81 against 9.8). At the start of single support the resultant departs "
          "from the weight by the mass times the vertical acceleration of the centre of mass that the trajectory "
          "imposes (cubics start at rest but not with zero acceleration): below the weight when the centre of mass "
          "starts downwards. The study's 83.3 N is 2.9 N (3.4 %) under its own static weight: either its step started with the "
          "centre of mass accelerating downwards at about 0.33 m/s², or its model weighed about 8.5 kg; it publishes "
          "neither its via points nor its mass table, so ours differ.")
        w("")
        for n in ("pendulum", "step"):
            if os.path.exists(os.path.join(scenes_dir, n + "_resultant.png")):
                w(f"![resultant force and ZMP during the step ({n})]({rel}/{n}_resultant.png)")
                w("")
                break


def ilqr_section(w, ilqr_dir):
    """The iLQR example of issue 13 (`spatial-ilqr`, written by scripts/main.sh into build/report/ilqr/)."""
    path = os.path.join(ilqr_dir, "summary.json")
    if not os.path.exists(path):
        return
    with open(path) as f:
        s = json.load(f)
    w("## iLQR with the analytical derivatives (issue 13)")
    w("")
    w(f"`spatial-ilqr` (tools/ilqr.hpp, tools/ilqr_example.cpp): the {s['model']} arms ({s['dof']} joints) from rest "
      f"to a target pose in {s['steps'] * s['dt']:.1f} s ({s['steps']} steps of {s['dt']} s), torques within "
      f"±{s['torque_limit']:g} N m, by one iLQR solver fed either by `aba_derivatives` or by forward finite "
      f"differences of ABA (3n + 1 calls per knot). Wall times: medians over {s['repeat']} solves of every iteration "
      f"(this run, this machine).")
    w("")
    rows = []
    for name, v in s["variants"].items():
        rows.append([name.replace("_", " "), str(v["iterations"]) + (" (converged)" if v["converged"] else ""),
                     f"{v['initial_cost']:.4g} → {v['final_cost']:.4g}", f"{v['median_iteration_ms']:.3f} ms",
                     f"{v['median_derivative_ms']:.3f} ms", f"{v['max_torque_ratio']:.3f}",
                     f"{v['final_pose_error']:.1e} rad"])
    w(md_table(["derivatives", "iterations", "cost", "time per iteration", "of which derivatives",
                "max abs τ ÷ limit", "final pose error"], rows))
    w("")
    w(f"Finite differences ÷ analytical: {s['fd_over_analytical_iteration']:.2f} per iteration, "
      f"{s['fd_over_analytical_derivatives']:.2f} for the derivatives alone (the rest of an iteration is the solver's "
      f"own dense algebra, the same for both).")
    w("")
    if os.path.exists(os.path.join(ilqr_dir, "ilqr.png")):
        w("![iLQR: cost per iteration, joint positions and torques](ilqr/ilqr.png)")
        w("")


# The variants of `spatial-dyn walk` that scripts/main.sh runs, in table order (any other <output>/walk*/ follows).
WALK_VARIANTS = ["walk", "walk_turn", "walk_no_second_stage", "walk_pendulum"]


def read_walks(out_dir):
    """{directory name: walk.json} for every <out_dir>/walk*/walk.json, main.sh's variants first."""
    names = sorted(n for n in os.listdir(out_dir) if n.startswith("walk")) if os.path.isdir(out_dir) else []
    walks = {}
    for n in sorted(names, key=lambda n: (WALK_VARIANTS.index(n) if n in WALK_VARIANTS else len(WALK_VARIANTS), n)):
        path = os.path.join(out_dir, n, "walk.json")
        if not os.path.exists(path):
            continue
        try:
            with open(path) as f:
                walks[n] = json.load(f)
        except (OSError, ValueError) as e:
            print(f"report.py: skipping {path}: {e}", file=sys.stderr)
    return walks


def walking_section(w, out_dir):
    """The closed-loop walk of the HOAP-3 (`spatial-dyn walk`, variants written by scripts/main.sh into
    build/report/walk*/): one table row per variant, the plots of the default walk. Returns the summary.json record
    of the default walk (None without it)."""
    walks = read_walks(out_dir)
    if not walks:
        return None
    w("## Walking (closed loop)")
    w("")
    w("`spatial-dyn walk` (include/spatial/walking/, docs/walking.md): the HOAP-3 with a floating base walks its "
      "footstep plan. Open loop, the whole-body generator turns the preview controller's cart-table CoM into joint "
      "motion and torques, and the second stage (`--second-stage N` passes) corrects the CoM against the ZMP of the "
      "ZMP model (the whole multibody, or the double pendulum); the open-loop column is the multibody ZMP's error "
      "against the reference after the last pass. Closed loop, the controller's joint torques (PD gains from "
      "`pd_frequency`) drive the rigid-contact simulator (walking/simulation.hpp: contacts made and broken at the "
      "plan's instants, impacts by impulse dynamics). Margins: distance of the simulated centre of pressure inside "
      "the support polygon (CoP) and inside the sole in contact (sole CoP); the friction ratio abs(F_t)/F_n is against "
      "μ; torque ratio: the closed loop's peak abs(τ) over the motor's rated torque. One row per variant that ran "
      "(scripts/main.sh: default, turning, without the second stage, double-pendulum ZMP model, the data sheet's public walk).")
    w("")
    rows = []
    for n, s in walks.items():
        p, cl, t = s["parameters"], s["closed_loop"], s["timings"]
        last = (s["open_loop"].get("passes") or [None])[-1]
        worst = max(s.get("torques", []), key=lambda e: e["rated_ratio"], default=None)
        turn = f", turn {p['turn']:g} rad" if p.get("turn") else ""
        rows.append([n, f"{p['steps']} × {p['length'] * 1e3:.0f} mm{turn}, {p['zmp_model'].replace('_', ' ')}, "
                        f"second stage {p['second_stage_iterations']}",
                     "yes" if cl["walked"] else "**no**", f"{cl['steps_completed']}/{p['steps']}",
                     fmt_mm(cl["cop_min_margin"]), fmt_mm(cl["sole_cop_min_margin"]), f"{cl['min_normal_force']:.1f}",
                     f"{cl['max_friction_ratio']:.2f} (μ {p['friction']:g})", fmt_mm(cl["pelvis_final_error"]),
                     f"{cl['joint_error_max']:.3g}",
                     f"{fmt_mm(last['zmp_error_max'])} / {fmt_mm(last['zmp_error_rms'])}" if last else "–",
                     f"{worst['rated_ratio']:.2f} ({worst['joint'].replace('_joint', '')})" if worst else "–",
                     f"{t['tick_fraction']:.1e}"])
    w(md_table(["variant", "plan", "walked", "steps", "CoP min margin [mm]", "sole CoP min margin [mm]",
                "min F_n [N]", "max abs(F_t)/F_n", "pelvis final error [mm]", "joint error max [rad]",
                "open-loop ZMP error max / RMS [mm]", "max abs(τ)/rated (joint)", "tick ÷ 2 ms"], rows))
    w("")
    default = walks.get("walk")
    if default is None:
        return None
    t = default["timings"]
    w(f"Default walk, wall time on this shared machine: one 2 ms control tick {t['tick_us']:.1f} µs, i.e. "
      f"{t['tick_fraction']:.1e} of the 2 ms period; one simulation step "
      f"({default['parameters']['simulation_dt'] * 1e3:g} ms) {t['simulation_step_us']:.1f} µs; the open-loop plan "
      f"{t['open_loop_s']:.2f} s and the closed loop {t['closed_loop_s']:.2f} s for {default['duration']:.2f} s "
      f"walked ({t['closed_loop_s'] / default['duration']:.2f} of real time).")
    w("")
    for name, title in (("walk_top.png", "top view: footprints, ZMP, centre of pressure, CoM"),
                        ("walk_zmp_error.png", "ZMP errors, CoP margin and normal forces"),
                        ("walk_torques.png", "joint torques against the rated and maximum torques")):
        if os.path.exists(os.path.join(out_dir, "walk", name)):
            w(f"![walk: {title}](walk/{name})")
            w("")
    return {"kind": "walking", "robot": default.get("robot"), "variant": "walk",
            "walking": {"closed_loop": default["closed_loop"], "timings": default["timings"]}}


def python_section(w, out_dir):
    """The Python package of issue 14, from <out_dir>/python/: bench/python_bench.py's tables (bench.md, included as
    written) and tools/python_torque_map.py's torque maps (torque_map.json, torque_map.png)."""
    pdir = os.path.join(out_dir, "python")
    w("## Python package (issue 14)")
    w("")
    if not os.path.isdir(pdir):
        w(f"Not run: no `{pdir}` (bench/python_bench.py and tools/python_torque_map.py write it, with the package "
          "installed).")
        w("")
        return
    bench_md = os.path.join(pdir, "bench.md")
    if os.path.exists(bench_md):
        w("Performance of the nanobind extension (`bench/python_bench.py`; its JSON: `python/bench.json`):")
        w("")
        with open(bench_md) as f:
            w(f.read().rstrip())
        w("")
    else:
        w("Performance (`bench/python_bench.py`): not run.")
        w("")
    path = os.path.join(pdir, "torque_map.json")
    if not os.path.exists(path):
        w("Torque map (`tools/python_torque_map.py`): not run.")
        w("")
        return
    try:
        with open(path) as f:
            tm = json.load(f)
    except (OSError, ValueError) as e:
        print(f"report.py: skipping {path}: {e}", file=sys.stderr)
        return
    g, call = tm["grid"], tm["batch_call"]
    w(f"The example of the package (`tools/python_torque_map.py`): the HOAP-3 standing on its right sole "
      f"(`load_urdf(..., root='{tm['model']['root']}')`, head and wrists locked), gravity torques over "
      f"{g['points_per_axis']} × {g['points_per_axis']} poses of the stance leg's hip pitch × knee within their URDF "
      f"limits, every other joint at 0, in one `{call['call']}` batch call ({call['seconds'] * 1e3:.2f} ms of wall "
      f"time, {fmt_ns(call['ns_per_state'])} per pose, on one thread). Limit = the motor's maximum torque (the URDF "
      "effort); rated: the data sheet's rated torque.")
    w("")
    rows = []
    for j in tm["joints"]:
        at = j["max_abs_tau_at"]
        frac = j["fraction_beyond_limit"]
        rated = j["fraction_beyond_rated"]
        rows.append([f"{j['title']} ({j['joint'].replace('_joint', '')})", f"{j['effort_limit_Nm']:g}",
                     f"{j['rated_Nm']:g}" if j["rated_Nm"] else "–", f"{j['max_abs_tau_Nm']:.3f}",
                     f"{math.degrees(at['hip_pitch_rad']):.0f}°, {math.degrees(at['knee_rad']):.0f}°",
                     f"{100 * frac:.1f} %" if frac is not None else "–",
                     f"{100 * rated:.1f} %" if rated is not None else "–"])
    w(md_table(["joint", "limit [N m]", "rated [N m]", "max abs(τ) [N m]", "at hip pitch, knee",
                "grid beyond the limit", "grid beyond rated"], rows))
    w("")
    if tm.get("plot") and os.path.exists(os.path.join(pdir, tm["plot"])):
        w(f"![gravity torques of the stance leg against the motor limits](python/{tm['plot']})")
        w("")


def general_section(w, records, compiler_list):
    """Trees with multi-DoF joints (general.hpp, bench_general): ball38 against Pinocchio, and the general tree on the
    one-DoF models beside their run-time trees and Pinocchio."""
    general = [r for r in records if r["tree"] == "general"]
    if not general:
        return
    w("## Spherical joints (issue 11): trees of multi-DoF joints")
    w("")
    w(f"`GeneralModel` (general.hpp): spherical joints and free-flyers anywhere in a run-time tree, scalar code. "
      f"{GENERAL_MODEL} is a humanoid whose hips, ankles, shoulders, wrists and neck are spherical joints (free-flyer "
      "pelvis; nq = 48, nv = 38), against Pinocchio's model of the same numbers (`JointModelSpherical`; bench_general "
      "checks τ, H and v̇ against ours before timing). On the HOAP-3 models the general tree is timed beside the "
      "run-time tree of the one-DoF code (its AVX2 kernels where the joints allow) and Pinocchio, to show what the "
      "generality costs where it is not needed.")
    w("")
    rows = []
    for model in (GENERAL_MODEL, TARGET_MODEL, FLOATING_MODEL):
        for algorithm in ("RNEA", "CRBA", "ABA"):
            for c in compiler_list:
                g = find(general, compiler=c, model=model, algorithm=algorithm, scalar="double")
                if not g:
                    continue
                rt = find(records, compiler=c, model=model, algorithm=algorithm, scalar="double", tree="runtime")
                pin = g["pinocchio_ns"]
                rows.append([model, algorithm, c, fmt_ns(g["ns"]), fmt_ns(rt["ns"]) if rt else "–",
                             fmt_ratio(ratio(g["ns"], rt["ns"] if rt else None)), fmt_ns(pin) if pin else "–",
                             fmt_ratio(ratio(g["ns"], pin))])
    w(md_table(["model", "algorithm", "compiler", "general tree", "run-time tree (one-DoF code)",
                "general ÷ run-time", "Pinocchio", "general ÷ Pinocchio"], rows))
    w("")


def write_report(out_dir, compilers, records, time_kind, charts_enabled=True, scenes_dir=None):
    os.makedirs(out_dir, exist_ok=True)
    notes = []
    machine = machine_info()
    have_pinocchio = {c: any(k[0] == "pinocchio" for k in e["times"]) for c, e in compilers.items()}
    have_kdl = {c: any(k[0] == "kdl" for k in e["times"]) for c, e in compilers.items()}
    batch_records = build_batch(compilers, time_kind, records)
    charts = write_charts(out_dir, records, compilers, notes, batch_records) if charts_enabled else []

    lines = []
    w = lines.append
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    w("# spatial: benchmark report")
    w("")
    w(f"Generated {now} by `tools/report.py` from the benchmark and error-study outputs of this run "
      f"(`bash scripts/main.sh`). Every number below was measured in that run unless marked *fixed* or *quoted*.")
    w("")
    w("## Machine and build")
    w("")
    rows = [["CPU", machine.get("model_name")],
            ["cores / logical CPUs", f"{machine.get('cores') or '?'} / {machine.get('cpus')}"],
            ["SIMD", ", ".join(machine.get("simd", [])) or "?"],
            ["kernel", machine.get("kernel")]]
    for c, e in compilers.items():
        rows.append([f"{c}: compiler", first_context_value(e, "spatial_compiler") or "?"])
        rows.append([f"{c}: flags (spatial, Pinocchio)", f"`{context_value(e, 'bench_algorithms', 'spatial_flags') or '?'}`"])
        if have_kdl[c]:
            rows.append([f"{c}: flags (KDL glue)", f"`{context_value(e, 'bench_kdl', 'spatial_flags') or '?'}` "
                         "(no -march=native: Debian's liborocos-kdl is built for generic x86-64)"])
        rows.append([f"{c}: Eigen (spatial / Pinocchio)",
                     f"{context_value(e, 'bench_algorithms', 'spatial_eigen') or '?'} / "
                     f"{context_value(e, 'bench_pinocchio', 'spatial_eigen') or '–'}"])
        rows.append([f"{c}: benchmark date, load average", f"{first_context_value(e, 'date') or '?'}, "
                     f"{', '.join(f'{x:.2f}' for x in (first_context_value(e, 'load_avg') or []))}"])
    kdl_version = next((context_value(e, "bench_kdl", "kdl_version") for e in compilers.values()
                        if context_value(e, "bench_kdl", "kdl_version")), None)
    pin_version = next((context_value(e, "bench_pinocchio", "pinocchio_version") for e in compilers.values()
                        if context_value(e, "bench_pinocchio", "pinocchio_version")), None)
    rows.append(["KDL", kdl_version or "absent"])
    rows.append(["Pinocchio", f"{pin_version} (pip package `pin`, header-only)" if pin_version else "absent"])
    lib_type = next((first_context_value(e, "library_build_type") for e in compilers.values()
                     if first_context_value(e, "library_build_type")), None)
    if lib_type:
        rows.append(["Google Benchmark library", f"{lib_type} build (Debian's libbenchmark; only its bookkeeping "
                     "between timed batches, not the timed loop, runs in that library)"])
    rows.append(["time statistic", f"median over repetitions of the {'CPU' if time_kind == 'cpu' else 'wall'} time "
                 "per call (scripts/main.sh runs the repetitions of a binary's benchmarks in random order, interleaved, "
                 "so that a slow spell of the host does not take all of one benchmark's); each call takes a fresh state from a pool of 256 random states (q uniform within the URDF "
                 "joint limits, q̇, q̈, τ uniform in [−1, 1])"])
    rows.append(["models", "HOAP-3 from urdf/hoap3.urdf (src/models/): stance21 = whole body on the right foot "
                 "(21 DoF), torso8 = chest and arms (8 DoF), pendulum2 = the study's double inverted pendulum"])
    w(md_table(["", ""], rows))
    w("")

    compiler_list = list(compilers)
    w(f"## Headline: {TARGET_MODEL}, double, compile-time tree")
    w("")
    header, rows = headline_rows(records, compiler_list)
    w(md_table(header, rows))
    w("")
    w("÷ Pinocchio, ÷ KDL: our time divided by the peer's (below 1: we are faster), same compiler, same model and "
      "inputs. ÷ 2 ms: fraction of the 2 ms control period. Errors: against long double (see below).")
    w("")

    w("## Performance targets (issue 4)")
    w("")
    header, rows = target_rows(records, compiler_list, have_pinocchio)
    w(md_table(header, rows))
    w("")
    w("Measured ratio = median time of spatial (compile-time tree, double) ÷ median time of the peer call, same run, "
      "same compiler and flags. Where a target is missed, `valgrind --tool=callgrind` on a build with "
      "`-march=x86-64-v3` (valgrind has no AVX-512) shows where the instructions go.")
    w("")
    missed = [(row[0], row[1]) for row in rows if row[4] == "miss"]
    if missed:
        w("Missed here, why, and what would close it (docs/performance.md has the measurements):")
        w("")
        for title, c in missed:
            algorithm = next(t[1] for t in TARGETS if t[0] == title)
            note = MISS_NOTES.get((algorithm, c), MISS_NOTES.get((algorithm, None),
                                  "no analysis recorded for this target; see docs/performance.md."))
            w(f"- {title}, {c}: {note}")
        w("")

    w(f"## Floating base (issue 11): {FLOATING_MODEL}")
    w("")
    w("The HOAP-3 free-flying at the pelvis (`hoap3_floating`: free-flyer + 21 joints, nq = 28, nv = 27), against "
      "Pinocchio's `JointModelFreeFlyer` model of the same robot built from the same numbers (bench_pinocchio checks "
      "τ, H and v̇ against ours before timing), on 256 states: root anywhere in a 1 m box with a random orientation, "
      "joints within their limits. The table after the targets has every floating-base benchmark, among them the "
      "contacts of issue 12 (`ContactDynamics_6D`: the left sole welded, `ContactDynamics_2x6D`: both soles, "
      "`ImpulseDynamics_2x6D`: an inelastic impact on both; against Pinocchio's `constraintDynamics` and "
      "`impulseDynamics`, checked against ours first; no target was set for them).")
    w("")
    header, rows = target_rows(records, compiler_list, have_pinocchio, FLOATING_TARGETS, FLOATING_MODEL)
    w(md_table(header, rows))
    w("")
    frows = []
    for algorithm in sorted({r["algorithm"] for r in records if r["model"] == FLOATING_MODEL}, key=algorithm_sort_key):
        for c in compiler_list:
            st = find(records, compiler=c, model=FLOATING_MODEL, algorithm=algorithm, scalar="double", tree="static")
            rt = find(records, compiler=c, model=FLOATING_MODEL, algorithm=algorithm, scalar="double", tree="runtime")
            pin = st["pinocchio_ns"] if st else None
            frows.append([algorithm, c, fmt_ns(st["ns"]) if st else "–", fmt_ns(rt["ns"]) if rt else "–",
                          fmt_ns(pin) if pin else "–", fmt_ratio(ratio(st["ns"] if st else None, pin)),
                          fmt_ratio(ratio(rt["ns"] if rt else None, pin))])
    w(md_table(["algorithm", "compiler", "compile-time tree", "run-time tree", "Pinocchio", "÷ Pinocchio (ct)",
                "÷ Pinocchio (rt)"], frows))
    w("")
    walk = [(c, find(records, compiler=c, model=FLOATING_MODEL, algorithm="WalkTick", scalar="double", tree="static"))
            for c in compiler_list]
    walk = [(c, r) for c, r in walk if r]
    if walk:
        w("Real time (issue 12): one tick of the whole-body walking generator (`WalkTick`: the preview step, the "
          "warm-started IK, v and v̇ by differential IK, contact inverse dynamics and the multibody ZMP) takes " +
          ", ".join(f"{fmt_ns(r['ns'])} ({100.0 * r['ns'] / 2e6:.2f} % of the 2 ms period) with {c}" for c, r in walk) +
          " on one core.")
        w("")

    general_section(w, records, compiler_list)

    w("## Derivatives (issue 13)")
    w("")
    w("Analytical derivatives of RNEA (∂τ/∂q, ∂τ/∂q̇) and of forward dynamics (∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ; on floating27 in "
      "the tangent space), against Pinocchio's `computeRNEADerivatives` / `computeABADerivatives` (bench_pinocchio "
      "checks all five matrices against ours before timing), H⁻¹ computed directly (`inverse_inertia`, against "
      "`computeMinverse`, also checked first) and our own forward differences of RNEA "
      "(`RNEA_derivatives_fd`: the same two matrices from 2n + 1 RNEA calls).")
    w("")
    for model in (TARGET_MODEL, FLOATING_MODEL):
        header, rows = target_rows(records, compiler_list, have_pinocchio, DERIVATIVE_TARGETS, model)
        w(f"{model}:")
        w("")
        w(md_table(header, rows))
        w("")
    drows = []
    for model in (TARGET_MODEL, FLOATING_MODEL):
        for c in compiler_list:
            an = find(records, compiler=c, model=model, algorithm="RNEA_derivatives", scalar="double", tree="static")
            ab = find(records, compiler=c, model=model, algorithm="ABA_derivatives", scalar="double", tree="static")
            fd = find(records, compiler=c, model=model, algorithm="RNEA_derivatives_fd", scalar="double",
                      tree="static")
            rt = find(records, compiler=c, model=model, algorithm="RNEA_derivatives", scalar="double", tree="runtime")
            mi = find(records, compiler=c, model=model, algorithm="Minv", scalar="double", tree="static")
            drows.append([model, c, fmt_ns(an["ns"]) if an else "–", fmt_ns(rt["ns"]) if rt else "–",
                          fmt_ns(ab["ns"]) if ab else "–", fmt_ns(mi["ns"]) if mi else "–",
                          fmt_ns(fd["ns"]) if fd else "–",
                          fmt_ratio(ratio(fd["ns"] if fd else None, an["ns"] if an else None))])
    w(md_table(["model", "compiler", "RNEA derivatives (ct)", "RNEA derivatives (rt)", "ABA derivatives (ct)",
                "H⁻¹ (ct)", "finite differences (ct)", "finite differences ÷ analytical"], drows))
    w("")
    arows = []
    for c in compiler_list:
        for algorithm in RNEA_DERIVATIVES:
            for scalar in ("double", "float"):
                r = find(records, compiler=c, model=TARGET_MODEL, algorithm=algorithm, scalar=scalar, tree="static") \
                    or find(records, compiler=c, model=TARGET_MODEL, algorithm=algorithm, scalar=scalar, tree="runtime")
                if r and r["max_rel_error"] is not None:
                    arows.append([c, ALGORITHM_TITLES.get(algorithm, algorithm), scalar, fmt_ns(r["ns"]),
                                  f"{r['max_rel_error']:.1e}", f"{r['median_rel_error']:.1e}"])
    if arows:
        w(f"Accuracy against run time on {TARGET_MODEL} (error study: max and median over 64 states of "
          "‖y − y_ref‖∞ / ‖y_ref‖∞ for y = [∂τ/∂q ∂τ/∂q̇], against the analytical derivatives in long double; "
          "forward differences with step √ε, central with ∛ε; these are also points of the run-time-against-error "
          "chart):")
        w("")
        w(md_table(["compiler", "method", "scalar", "time per call", "max rel. error", "median rel. error"], arows))
        w("")

    batch_section(w, batch_records, compiler_list)

    w("## Reference rows")
    w("")
    rows = []
    for title, model, algorithm, matlab_ns in MATLAB_ROWS:
        row = [title, fmt_ns(matlab_ns)]
        for c in compiler_list:
            r = find(records, compiler=c, model=model, algorithm=algorithm, scalar="double", tree="static")
            row.append(f"{fmt_ns(r['ns'])} ({r['ns'] / matlab_ns:.1e})" if r else "–")
        rows.append(row)
    w("*Fixed*: the reference study's MATLAB times (issue 4), against ours (in parentheses: our time ÷ MATLAB's).")
    w("")
    w(md_table(["reference study (MATLAB)", "time (fixed)"] + [f"spatial {c}" for c in compiler_list], rows))
    w("")
    w("*Quoted* from issue 4 for orientation (fastest peer builds measured on this kind of machine for a 21-joint "
      "humanoid; not measured here, and on their own humanoid models, not on our HOAP-3 stance21):")
    w("")
    rows = []
    for who, what, ns in ORIENTATION_ROWS:
        algorithm = {"sparse LTDL": "LTDL"}.get(what, what)
        row = [who, what, fmt_ns(ns)]
        for c in compiler_list:
            r = find(records, compiler=c, model=TARGET_MODEL, algorithm=algorithm, scalar="double", tree="static") \
                if algorithm else None
            row.append(fmt_ns(r["ns"]) if r else "–")
        rows.append(row)
    w(md_table(["peer build", "call", "time (quoted)"] + [f"spatial {c}, {TARGET_MODEL}" for c in compiler_list], rows))
    w("")

    w("## Time per call, every model and algorithm")
    w("")
    w("static = compile-time tree, runtime = run-time tree. Peer columns: the peer's time for the same model, "
      "algorithm and scalar ('–' where the peer has no such call or is absent).")
    w("")
    for model in model_names(records):
        w(f"### {model}")
        w("")
        rows = []
        keys = sorted({(r["algorithm"], r["scalar"], r["tree"]) for r in records if r["model"] == model},
                      key=lambda k: (algorithm_sort_key(k[0]), k[1], k[2] != "static"))
        for algorithm, scalar, tree in keys:
            row = [algorithm, scalar, tree]
            for c in compiler_list:
                r = find(records, compiler=c, model=model, algorithm=algorithm, scalar=scalar, tree=tree)
                row += [fmt_ns(r["ns"]) if r else "–", f"{r['ratio_to_control_period']:.1e}" if r else "–",
                        fmt_ns(r["pinocchio_ns"]) if r else "–", fmt_ratio(r["ratio_to_pinocchio"]) if r else "–",
                        fmt_ns(r["kdl_ns"]) if r else "–", fmt_ratio(r["ratio_to_kdl"]) if r else "–"]
            r = find(records, model=model, algorithm=algorithm, scalar=scalar)
            row.append(fmt_err(r["max_rel_error"] if r else None))
            rows.append(row)
        header = ["algorithm", "scalar", "tree"]
        for c in compiler_list:
            header += [f"{c}", f"{c} ÷ 2 ms", f"Pinocchio {c}", f"÷ Pin. {c}", f"KDL {c}", f"÷ KDL {c}"]
        header.append("max rel. error")
        w(md_table(header, rows))
        w("")
    w("Peer calls: " + "; ".join(f"{peer} {ALGORITHM_TITLES.get(a, a)} = `{call}`"
                                 for (peer, a), call in PEER_CALLS.items()) + ". Pinocchio's crba computes the upper "
      "triangle of H only (ours fills both triangles); its forward dynamics by CRBA recomputes the kinematics in "
      "nonLinearEffects (ours shares them). KDL's ChainFdSolver_RNE = ChainDynParam inertia + RNEA bias + dense LDLᵀ, "
      "listed against our forward dynamics by CRBA + LTDL. Our dense-Cholesky variant (FD_CRBA_DenseLLT) calls "
      "bias_forces and crba separately, each computing its own transforms.")
    w("")

    w("## Error against long double")
    w("")
    first = next((e["error"] for e in compilers.values() if e.get("error")), None)
    if first:
        w(f"Error = {first.get('error_definition')} over {first.get('samples')} random states; reference: the same "
          f"algorithm in long double ({first.get('long_double_digits')}-bit mantissa) on `model.cast<long double>()`. "
          "Float and double run on the double model and inputs cast down (parameter and input rounding included). "
          "The errors are measured on the run-time tree, which runs the same per-joint code as the compile-time tree.")
        w("")
        rows = []
        keys = sorted({(p["model"], p["algorithm"]) for p in first["algorithms"]},
                      key=lambda k: (model_names(records).index(k[0]) if k[0] in model_names(records) else 99,
                                     algorithm_sort_key(k[1])))
        for model, algorithm in keys:
            row = [model, algorithm]
            for c in compiler_list:
                err = compilers[c].get("error") or {}
                by = {(p["model"], p["algorithm"], p["scalar"]): p for p in err.get("algorithms", [])}
                for scalar in ("float", "double"):
                    p = by.get((model, algorithm, scalar))
                    row.append(fmt_err(p["max_rel_error"]) if p else "–")
            rows.append(row)
        header = ["model", "algorithm"] + [f"{s} ({c})" for c in compiler_list for s in ("float", "double")]
        w(md_table(header, rows))
        w("")
    else:
        w("No error study output.")
        w("")

    w(f"## Run time against error ({TARGET_MODEL})")
    w("")
    w("One point per variant: x = median time per call (compile-time tree), y = max relative error. "
      "★ = on the Pareto front of its result: no other variant computing the same result is both faster and more "
      "accurate. The three forward dynamics (ABA, CRBA + tree LTDL, CRBA + dense Cholesky; float and double) "
      "compete with each other; every other algorithm competes with itself in the other scalar type. Batched "
      f"variants (`…_batch`, issue 15): time per state on one thread at B = {BATCH_TARGET_B}, compile-time tree, "
      "error of the batched call (error study), competing with the single-state calls of the same result.")
    w("")
    for c in compiler_list:
        pts = variant_points(records, c, batch_records)
        if not pts:
            continue
        front = grouped_pareto(pts)
        rows = [[group, label, fmt_ns(x), fmt_err(y), "★" if i in front else ""]
                for i, (x, y, label, _, group) in sorted(enumerate(pts), key=lambda t: (t[1][4], t[1][0]))]
        w(f"**{c}**")
        w("")
        w(md_table(["result", "variant", "time", "max rel. error", "Pareto"], rows))
        w("")
    sim_first = next((e["error"]["simulation"] for e in compilers.values() if e.get("error")), None)
    if sim_first:
        ref = sim_first.get("reference", {})
        w(f"### Integrators: {sim_first.get('model')}, {sim_first.get('duration_s')} s simulated")
        w("")
        w(f"From a random state, τ = −{sim_first.get('damping')} q̇, forward dynamics by ABA (compile-time tree, "
          f"double). Error = max |q(1 s) − q_ref(1 s)| [rad] against {ref.get('method')} in {ref.get('scalar')} with "
          f"step {ref.get('dt')} s. Cost = median CPU time per simulated second (×1e-9 = fraction of real time).")
        w("")
        rows = []
        per_c = {c: simulation_points(e) for c, e in compilers.items()}
        fronts = {c: pareto_front([(p["ns_per_simulated_second"], p["max_abs_error_q"]) for p in pts])
                  for c, pts in per_c.items()}
        base = per_c[compiler_list[0]] if compiler_list else []
        for i, p in enumerate(base):
            row = [p["method"], f"{p['dt']:g}", p["steps"] * p["evaluations_per_step"]]
            for c in compiler_list:
                match = [j for j, q in enumerate(per_c[c]) if q["method"] == p["method"] and q["dt"] == p["dt"]]
                if match:
                    q = per_c[c][match[0]]
                    row += [fmt_ns(q["ns_per_simulated_second"]), fmt_err(q["max_abs_error_q"]),
                            "★" if match[0] in fronts[c] else ""]
                else:
                    row += ["–", "–", ""]
            rows.append(row)
        header = ["method", "step [s]", "ABA calls"]
        for c in compiler_list:
            header += [f"cost/sim. s ({c})", f"error [rad] ({c})", f"Pareto ({c})"]
        w(md_table(header, rows))
        w("")
    step_first = next((e["error"]["step_resultant"] for e in compilers.values()
                       if e.get("error") and e["error"].get("step_resultant")), None)
    if step_first:
        w("### The stepping scene: full model vs reduced models vs double pendulum")
        w("")
        w(f"The resultant force of the ground on the robot over the {step_first.get('samples')} samples of the step "
          "(`spatial-dyn scene step`), by each model, against the full 21-DoF model in long double. Reduced models: "
          "limbs locked at their angles at the start of the step (run-time trees from the URDF loader). "
          f"Error = {step_first.get('error_definition')}; Fz: max relative error of the vertical component; "
          "Fh: max absolute error of the horizontal components. Time = "
          f"{step_first.get('time_definition')}. ★ = on the Pareto front.")
        w("")
        rows = []
        for c in compiler_list:
            pts = step_points(compilers[c])
            front = set(pareto_front([(p["ns"], p["max_rel_error"]) for p in pts]))
            for i, p in enumerate(pts):
                rows.append([c, p["variant"], p["dof"], p["scalar"], p["tree"], fmt_ns(p["ns"]),
                             fmt_err(p["max_rel_error"]), fmt_err(p.get("max_rel_error_Fz")),
                             f"{p.get('max_abs_error_Fh_N', float('nan')):.3g} N", "★" if i in front else ""])
        w(md_table(["compiler", "model", "DoF", "scalar", "tree", "time", "max rel. error", "Fz rel. error",
                    "Fh abs. error", "Pareto"], rows))
        w("")
    else:
        w("**Pending**: full 21-DoF model vs reduced models (locked limbs) vs double pendulum for the resultant "
          "force of the stepping scene: the error study was built without the URDF loader.")
        w("")

    savings = savings_rows(compilers)
    if savings:
        w("## Savings")
        w("")
        w("Paying only for what a scene uses (`bench_scenes`, include/spatial/options.hpp and reduce.hpp): each option "
          "against the full computation on the same model, inputs and tree, median time per call. ArmsOnly: the "
          "8 arm joints of the stance model moving, the rest held (`keep_branches`), against the whole body.")
        w("")
        w(md_table(["compiler", "algorithm", "option", "model", "tree", "time", "full computation", "ratio",
                    "saving"], savings))
        w("")

    growth = [r for r in records if r["kind"] == "growth"]
    if growth:
        w("## Cost growth")
        w("")
        w("Chains and balanced binary trees of n bodies (revolute joints cycling x, y, z; random inertias), double. "
          "k = least-squares slope of log(time) against log(n), i.e. time ∝ n^k. Compile-time trees only up to "
          "the size given by SPATIAL_GROWTH_MAX_STATIC (unrolling larger trees costs minutes of compile time); "
          "run-time trees for every size.")
        w("")
        rows = []
        for c in compiler_list:
            for (algorithm, shape, tree), pts in growth_series(growth, c).items():
                k = fit_exponent(pts)
                rows.append([c, algorithm, shape, tree, f"{pts[0][0]}–{pts[-1][0]}",
                             f"{k:.2f}" if k is not None else "–",
                             " · ".join(f"{n}: {fmt_ns(t)}" for n, t in pts)])
        w(md_table(["compiler", "algorithm", "shape", "tree", "n", "k", "time per call by n"], rows))
        w("")

    scenes_section(w, scenes_dir or os.path.join(out_dir, "scenes"), out_dir)
    ilqr_section(w, os.path.join(out_dir, "ilqr"))
    walking = walking_section(w, out_dir)
    python_section(w, out_dir)

    if charts:
        w("## Charts")
        w("")
        for title, name in charts:
            w(f"**{title}**")
            w("")
            w(f"![{title}]({name})")
            w("")
    if notes or not all(have_pinocchio.values()):
        w("## Notes")
        w("")
        for c, ok in have_pinocchio.items():
            if not ok:
                w(f"- Pinocchio: absent for {c} (scripts/peers.sh could not install `pin`, or the build did not "
                  f"find it); its columns are '–' and its targets 'absent'.")
        for n in notes:
            w(f"- {n}")
        w("")

    with open(os.path.join(out_dir, "report.md"), "w") as f:
        f.write("\n".join(lines))
    with open(os.path.join(out_dir, "summary.json"), "w") as f:
        json.dump(records + batch_records + ([walking] if walking else []), f, indent=1)
    return notes


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--input", default="build/report/raw")
    ap.add_argument("--output", default="build/report")
    ap.add_argument("--time", choices=["cpu", "real"], default="cpu")
    ap.add_argument("--no-charts", action="store_true")
    ap.add_argument("--scenes", default=None, help="scene outputs (default: <output>/scenes)")
    args = ap.parse_args()

    compilers = read_inputs(args.input, args.time)
    if not compilers:
        sys.exit(f"report.py: no benchmark output under {args.input}")
    records = build(compilers, args.time)
    write_report(args.output, compilers, records, args.time, charts_enabled=not args.no_charts,
                 scenes_dir=args.scenes)

    header, rows = headline_rows(records, list(compilers))
    print(f"\nHeadline: {TARGET_MODEL}, double, compile-time tree ({args.time} time, median)\n")
    print(text_table(header, rows))
    have_pinocchio = {c: any(k[0] == "pinocchio" for k in e["times"]) for c, e in compilers.items()}
    header, rows = target_rows(records, list(compilers), have_pinocchio)
    print("\nPerformance targets (issue 4)\n")
    print(text_table(header, rows))
    header, rows = target_rows(records, list(compilers), have_pinocchio, FLOATING_TARGETS, FLOATING_MODEL)
    print(f"\nFloating-base targets (issue 11, {FLOATING_MODEL})\n")
    print(text_table(header, rows))
    for model in (TARGET_MODEL, FLOATING_MODEL):
        header, rows = target_rows(records, list(compilers), have_pinocchio, DERIVATIVE_TARGETS, model)
        print(f"\nDerivative targets (issue 13, {model})\n")
        print(text_table(header, rows))
    batch_records = build_batch(compilers, args.time, records)
    if batch_records:
        header, rows = batch_target_rows(batch_records, list(compilers))
        print(f"\nBatched targets (issue 15, {TARGET_MODEL}, compile-time tree, time per state)\n")
        print(text_table(header, rows))
    print(f"\nreport.py: wrote {os.path.join(args.output, 'report.md')}, summary.json and charts")


if __name__ == "__main__":
    main()
