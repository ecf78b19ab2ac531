#!/usr/bin/env python3
"""Performance of the Python package (issue 14): the cost of one call from Python, and the throughput of batches.

(a) One call: `spatial.rnea(stance21, q, v, a)` (and `spatial.aba`) from Python, the same state every call, against
    - the same call in C++: the median CPU time of `spatial/RNEA/stance21/double/static` (and ABA) in the Google
      Benchmark JSON of the main job (`<cpp>/raw/<compiler>/bench_*.json`, else `<cpp>/summary.json`; "missing" when
      neither exists). The C++ benchmark takes each call's state from a pool of 256;
    - Pinocchio's Python `pin.rnea(model, data, q, v, a)` (and `pin.aba`) on the same robot: `pin.buildModelFromUrdf`
      of urdf/hoap3.urdf + `pin.buildReducedModel` with the same locked joints (head and wrists at 0). Pinocchio's
      model is rooted at base_link (the pelvis), ours at R_SOLE: the same 21 joints and bodies, a different root, which
      does not matter for timing; and, for reference, the C++ figure of Pinocchio's rnea from bench_pinocchio
      (its model is converted from our stance21 there, rooted at R_SOLE).
    Time per call = median over repeats of the CPU time of a timeit loop (the C++ figures are CPU times too); the
    wall time is recorded beside it.
(b) Batches of 1e4 and 1e6 states (q within the URDF limits, v, q̈, τ uniform in [−1, 1]; (B, n) C-contiguous
    float64 arrays): `spatial.rnea` and `spatial.aba` batch calls with threads=1 and threads=0 (all cores), the same
    on SIMD lanes (`spatial.Batch(m, threads).rnea` / `.aba`, C++ batch.hpp, its pool of threads started once), against a
    Python loop over `pin.rnea` / `pin.aba` (and over `spatial.rnea`) — measured on 1e4 states and extrapolated to 1e6
    (the per-state time of a loop does not depend on the batch size; the JSON marks these rows `extrapolated`) — and
    against Pinocchio's own batch API, `pin.rneaInParallel` / `pin.abaInParallel` with a `pin.ModelPool` (states as
    columns: the transposes of the same arrays, F-contiguous, which it reads without a copy), when the installed pin
    has it ("not available" otherwise). Throughput = states per second of wall time (the median over repeats).
    Checks on the way (in the JSON): threads=0 gives the same numbers as threads=1, a batch row the same as one call,
    spatial.Batch's rows within a few ulps of the functions' (relative to each state's largest |τ|),
    ABA inverts RNEA, and Pinocchio's batch matches its loop. On the smaller batch, one thread: the `Dyn` flag sets
    QuasiStatic and Static of `spatial.rnea`, `spatial.gravity` and `spatial.aba` with Static (what leaving terms out
    saves).
(c) The walking generator: one `spatial.walk()` (8 steps; 2 with --quick), its wall time beside its stages' own
    clocks (the open-loop passes, the closed-loop simulation).

Writes OUT/bench.json (every measurement, with clearly named fields) and OUT/bench.md (the tables, without a heading,
for tools/report.py's "Python package" section). Takes about 40 s on 2 cores (the 1e6-state batches take ~1 s each for
spatial, ~3-5 s each for Pinocchio's batch API, which therefore runs once there, on all cores only); --quick: small
sizes (for tests).
Usage: bench/python_bench.py [--out build/report/python] [--cpp build/report] [--quick]
"""

import argparse
import datetime
import functools
import gc
import importlib.util
import json
import math
import os
import platform
import statistics
import sys
import time
import timeit

import numpy as np

import spatial

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LOCKED = ["CHEST_H_PAN_joint", "H_PAN_H_TILT_joint", "H_TILT_H_ROLL_joint", "R_EB_R_WR_joint", "L_EB_L_WR_joint"]


# ---------------------------------------------------------------------------------------------------------------
# Timing
# ---------------------------------------------------------------------------------------------------------------
def measure(stmt, env, *, repeats, min_time=0.0, number=None):
    """Runs `stmt` (a statement with the names of `env`) `number` times per repeat, `repeats` times, with the garbage
    collector off (timeit). Without `number`, calibrates it first, as timeit's autorange does (1, 2, 5, 10, ... until
    one loop takes at least `min_time` of wall time; that loop is the warm-up). Returns per-execution medians of
    CPU (process) and wall time in ns, and the raw repeat times."""
    timer = timeit.Timer(stmt, globals=env)
    if number is None:
        number = 1
        while True:
            for k in (1, 2, 5):
                if timer.timeit(number * k) >= min_time:
                    number *= k
                    break
            else:
                number *= 10
                continue
            break
    walls, cpus = [], []
    for _ in range(repeats):
        c0 = time.process_time()
        wall = timer.timeit(number)
        cpus.append(time.process_time() - c0)
        walls.append(wall)
    return {"number": number, "repeats": repeats,
            "cpu_ns": statistics.median(cpus) / number * 1e9, "wall_ns": statistics.median(walls) / number * 1e9,
            "cpu_ns_min": min(cpus) / number * 1e9, "wall_ns_min": min(walls) / number * 1e9,
            "cpu_s_per_repeat": cpus, "wall_s_per_repeat": walls}


# ---------------------------------------------------------------------------------------------------------------
# The C++ figures of the main job
# ---------------------------------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=None)
def load_report_module():
    spec = importlib.util.spec_from_file_location("spatial_report", os.path.join(REPO, "tools", "report.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


CPP_KEYS = {
    "spatial_rnea_static": ("spatial", "RNEA", "stance21", "double", "static"),
    "spatial_rnea_runtime": ("spatial", "RNEA", "stance21", "double", "runtime"),
    "spatial_aba_static": ("spatial", "ABA", "stance21", "double", "static"),
    "spatial_aba_runtime": ("spatial", "ABA", "stance21", "double", "runtime"),
    "pinocchio_rnea": ("pinocchio", "RNEA", "stance21", "double", "-"),
    "pinocchio_aba": ("pinocchio", "ABA", "stance21", "double", "-"),
}


def cpp_figures(cpp_dir):
    """{name: {compiler: ns}} for CPP_KEYS, and where they came from: the raw Google Benchmark JSON of the main job
    (<cpp_dir>/raw/<compiler>/bench_*.json, read as tools/report.py reads it: median CPU time), else
    <cpp_dir>/summary.json (tools/report.py's records)."""
    figures = {k: {} for k in CPP_KEYS}
    raw = os.path.join(cpp_dir, "raw")
    sources = []
    if os.path.isdir(raw):
        try:
            report = load_report_module()
            compilers = report.read_inputs(raw, "cpu")
        except (Exception, SystemExit) as e:  # report.py exits when the directory holds nothing
            print(f"python_bench.py: could not read {raw}: {e}", file=sys.stderr)
            compilers = {}
        for compiler, entry in compilers.items():
            for name, key in CPP_KEYS.items():
                if key in entry["times"]:
                    figures[name][compiler] = entry["times"][key]
        if any(figures.values()):
            sources.append(raw)
    summary = os.path.join(cpp_dir, "summary.json")
    if not any(figures.values()) and os.path.exists(summary):
        try:
            with open(summary) as f:
                records = json.load(f)
            for r in records:
                if r.get("kind") != "model" or r.get("model") != "stance21" or r.get("scalar") != "double":
                    continue
                for name, (impl, algorithm, _, _, tree) in CPP_KEYS.items():
                    if r.get("algorithm") != algorithm:
                        continue
                    if impl == "spatial" and r.get("tree") == tree and r.get("ns"):
                        figures[name][r["compiler"]] = r["ns"]
                    elif impl == "pinocchio" and r.get("tree") == "static" and r.get("pinocchio_ns"):
                        figures[name][r["compiler"]] = r["pinocchio_ns"]
            if any(figures.values()):
                sources.append(summary)
        except (OSError, ValueError) as e:
            print(f"python_bench.py: could not read {summary}: {e}", file=sys.stderr)
    return figures, (sources[0] if sources else None)


# ---------------------------------------------------------------------------------------------------------------
# Formatting
# ---------------------------------------------------------------------------------------------------------------
def fmt_ns(ns):
    """tools/report.py's fmt_ns, with seconds for the 1e6-state batches (report.py has no figure that long)."""
    if ns is not None and ns >= 1e9:
        return f"{ns / 1e9:.3g} s"
    return load_report_module().fmt_ns(ns)


def fmt_delta(ns):
    return ("+" if ns >= 0 else "−") + fmt_ns(abs(ns))


def fmt_states(size):
    k = round(math.log10(size))
    return f"1e{k}" if 10 ** k == size else str(size)


def fmt_rate(r):
    if r is None:
        return "–"
    for unit, scale in (("G", 1e9), ("M", 1e6), ("k", 1e3)):
        if r >= scale:
            return f"{r / scale:.3g} {unit}/s"
    return f"{r:.3g} /s"


def md_table(header, rows):
    """tools/report.py's markdown table."""
    return load_report_module().md_table(header, rows)


def distribution_version(name):
    try:
        from importlib.metadata import version
        return version(name)
    except Exception:  # not installed as a distribution (e.g. on PYTHONPATH)
        return None


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


# ---------------------------------------------------------------------------------------------------------------
# The benchmark
# ---------------------------------------------------------------------------------------------------------------
def random_states(rng, lower, upper, n, size, qonly=False):
    lo = np.where(np.isfinite(lower), lower, -math.pi)
    hi = np.where(np.isfinite(upper), upper, math.pi)
    q = rng.uniform(lo, hi, size=(size, n))
    if qonly:
        return (q,)
    v = rng.uniform(-1.0, 1.0, size=(size, n))
    a = rng.uniform(-1.0, 1.0, size=(size, n))
    tau = rng.uniform(-1.0, 1.0, size=(size, n))
    return q, v, a, tau


def pin_rnea_loop(pin, model, data, Q, V, A):
    out = np.empty_like(A)
    for i in range(Q.shape[0]):
        out[i] = pin.rnea(model, data, Q[i], V[i], A[i])
    return out


def pin_aba_loop(pin, model, data, Q, V, T):
    out = np.empty_like(T)
    for i in range(Q.shape[0]):
        out[i] = pin.aba(model, data, Q[i], V[i], T[i])
    return out


def spatial_rnea_loop(model, Q, V, A):
    out = np.empty_like(A)
    for i in range(Q.shape[0]):
        out[i] = spatial.rnea(model, Q[i], V[i], A[i])
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="build/report/python", help="output directory (default build/report/python)")
    ap.add_argument("--cpp", default="build/report",
                    help="the main job's report directory, for the C++ figures (default build/report)")
    ap.add_argument("--quick", action="store_true", help="small sizes and short loops (for tests)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    start = time.perf_counter()
    load_start = list(os.getloadavg()) if hasattr(os, "getloadavg") else None

    if args.quick:
        sizes, loop_size, call_repeats, call_min_time = [100, 1000], 100, 3, 0.01
        batch_repeats, batch_min_time = 3, 0.01
    else:
        sizes, loop_size, call_repeats, call_min_time = [10_000, 1_000_000], 10_000, 5, 0.1
        batch_repeats, batch_min_time = 5, 0.05
    big = 100_000  # from this size on: one batch call per repeat (no calibration), 3 repeats; Pinocchio's batch once
    threads_all = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    notes = []

    try:
        import pinocchio as pin
    except ImportError as e:
        pin = None
        notes.append(f"Pinocchio's Python package is not importable ({e}): its rows are missing.")

    # --- models -------------------------------------------------------------------------------------------------
    stance = spatial.hoap3_stance_right()
    loaded = spatial.load_urdf(spatial.urdf_path("hoap3.urdf"), root="R_SOLE", lock={j: 0.0 for j in LOCKED})
    if list(stance.joint_names) != list(loaded.joint_names):
        notes.append("hoap3_stance_right() and load_urdf(..., root='R_SOLE', lock=head+wrists) list different joints "
                     "(API.md says they are the same).")
    n = stance.nv
    pmodel = pdata = None
    if pin is not None:
        full = pin.buildModelFromUrdf(spatial.urdf_path("hoap3.urdf"))
        pmodel = pin.buildReducedModel(full, [full.getJointId(j) for j in LOCKED], pin.neutral(full))
        pdata = pmodel.createData()
        if pmodel.nv != n:
            notes.append(f"Pinocchio's reduced model has nv = {pmodel.nv}, ours {n}.")

    rng = np.random.default_rng(14)
    lower, upper = np.asarray(stance.lower, float), np.asarray(stance.upper, float)
    q1, v1, a1, t1 = (x[0].copy() for x in random_states(rng, lower, upper, n, 1))
    env = {"spatial": spatial, "stance": stance, "loaded": loaded, "q": q1, "v": v1, "a": a1, "t": t1}
    if pin is not None:
        pq1, pv1, pa1, pt1 = (x[0].copy() for x in random_states(
            rng, pmodel.lowerPositionLimit, pmodel.upperPositionLimit, pmodel.nv, 1))
        env.update({"pin": pin, "pm": pmodel, "pd": pdata, "pq": pq1, "pv": pv1, "pa": pa1, "pt": pt1})

    # --- (a) one call ---------------------------------------------------------------------------------------------
    cpp, cpp_source = cpp_figures(args.cpp)
    if cpp_source is None:
        notes.append(f"No C++ benchmark output under {args.cpp} (raw/<compiler>/bench_*.json or summary.json): "
                     "the C++ column is missing.")
    calls = [
        ("spatial.rnea(hoap3_stance_right(), q, v, a)", "spatial", "RNEA", "compile-time tree",
         "spatial.rnea(stance, q, v, a)", "spatial_rnea_static"),
        ("spatial.rnea(load_urdf(...), q, v, a)", "spatial", "RNEA", "run-time tree",
         "spatial.rnea(loaded, q, v, a)", "spatial_rnea_runtime"),
        ("pin.rnea(model, data, q, v, a)", "pinocchio", "RNEA", "Pinocchio, rooted at base_link",
         "pin.rnea(pm, pd, pq, pv, pa)", "pinocchio_rnea"),
        ("spatial.aba(hoap3_stance_right(), q, v, tau)", "spatial", "ABA", "compile-time tree",
         "spatial.aba(stance, q, v, t)", "spatial_aba_static"),
        ("pin.aba(model, data, q, v, tau)", "pinocchio", "ABA", "Pinocchio, rooted at base_link",
         "pin.aba(pm, pd, pq, pv, pt)", "pinocchio_aba"),
    ]
    per_call = []
    for title, impl, algorithm, what, stmt, cpp_key in calls:
        if impl == "pinocchio" and pin is None:
            continue
        m = measure(stmt, env, repeats=call_repeats, min_time=call_min_time)
        cpp_ns = cpp.get(cpp_key, {})
        rec = {"call": title, "impl": impl, "algorithm": algorithm, "model": "stance21", "what": what,
               "ns_per_call_cpu": m["cpu_ns"], "ns_per_call_wall": m["wall_ns"],
               "ns_per_call_cpu_min": m["cpu_ns_min"], "ns_per_call_wall_min": m["wall_ns_min"], "number": m["number"],
               "repeats": m["repeats"], "cpp_benchmark": "/".join(CPP_KEYS[cpp_key]),
               "cpp_ns_per_call": cpp_ns or None,
               "python_overhead_ns": {c: m["cpu_ns"] - ns for c, ns in cpp_ns.items()} or None,
               "python_over_cpp": {c: m["cpu_ns"] / ns for c, ns in cpp_ns.items() if ns} or None}
        per_call.append(rec)
        print(f"  one call: {title}: {fmt_ns(m['cpu_ns'])} CPU ({fmt_ns(m['wall_ns'])} wall); C++: "
              + (", ".join(f"{c} {fmt_ns(ns)}" for c, ns in cpp_ns.items()) or "missing"), flush=True)

    def find_call(impl, algorithm, what_prefix):
        return next((r for r in per_call if r["impl"] == impl and r["algorithm"] == algorithm
                     and r["what"].startswith(what_prefix)), None)

    # --- (b) batches ----------------------------------------------------------------------------------------------
    batch, checks = [], {}
    pin_batch_api = None
    if pin is not None:
        if hasattr(pin, "rneaInParallel") and hasattr(pin, "abaInParallel") and hasattr(pin, "ModelPool"):
            pin_batch_api = "pin.rneaInParallel / pin.abaInParallel (pin.ModelPool)"
        else:
            batch_names = [x for x in dir(pin) if "batch" in x.lower() or "parallel" in x.lower()]
            notes.append("Pinocchio's batch API (rneaInParallel / abaInParallel) is not available in the installed pin"
                         + (f" (it has: {', '.join(batch_names)})" if batch_names else "") + ".")
    pool = pin.ModelPool(pmodel, threads_all) if pin_batch_api else None

    def add(size, impl, call, threads, m, extrapolated_from=None):
        """threads: the `threads=` argument (spatial: 0 = all cores; Pinocchio: the count)."""
        seconds = m["wall_ns"] * 1e-9  # one execution = one batch of `size` states
        rec = {"states": size, "impl": impl, "call": call, "threads": threads or threads_all,
               "threads_argument": threads,
               "seconds_per_batch_wall": seconds, "seconds_per_batch_cpu": m["cpu_ns"] * 1e-9,
               "ns_per_state_wall": seconds / size * 1e9, "states_per_second_wall": size / seconds,
               "states_per_second_cpu": size / (m["cpu_ns"] * 1e-9),
               "states_per_second_wall_best": size / (m["wall_ns_min"] * 1e-9),
               "repeats": m["repeats"], "batches_per_repeat": m["number"],
               "extrapolated": extrapolated_from is not None}
        if extrapolated_from is not None:
            rec["extrapolated_from_states"] = extrapolated_from
        batch.append(rec)
        print(f"  batch {size:>8} {call} threads={threads}: {rec['states_per_second_wall']:.4g} states/s "
              f"({fmt_ns(rec['ns_per_state_wall'])} per state" + (", extrapolated)" if extrapolated_from else ")"),
              flush=True)

    loop_per_state = {}
    # spatial.Batch: the same states on SIMD lanes (C++ batch.hpp), its thread pool started once, here
    lanes = {th: spatial.Batch(stance, threads=th) for th in (1, 0)}
    for size in sizes:
        Q, V, A, T = random_states(rng, lower, upper, n, size)
        benv = {"spatial": spatial, "m": stance, "Q": Q, "V": V, "A": A, "T": T,
                "spatial_rnea_loop": spatial_rnea_loop, "b1": lanes[1], "b0": lanes[0]}
        kw = {"repeats": 3, "number": 1} if size >= big else {"repeats": batch_repeats, "min_time": batch_min_time}
        for call, stmt in (("spatial.rnea", "spatial.rnea(m, Q, V, A, threads={th})"),
                           ("spatial.aba", "spatial.aba(m, Q, V, T, threads={th})")):
            for th in (1, 0):
                add(size, "spatial", call, th, measure(stmt.format(th=th), benv, **kw))
        for call, stmt in (("spatial.Batch(m).rnea", "b{th}.rnea(Q, V, A)"),
                           ("spatial.Batch(m).aba", "b{th}.aba(Q, V, T)")):
            for th in (1, 0):
                add(size, "spatial", call, th, measure(stmt.format(th=th), benv, **kw))
        if size == sizes[0]:  # the terms of the dynamics (spatial.Dyn) on one thread: what leaving terms out saves
            for call, stmt in (("spatial.rnea(m, Q, None, A, dyn=Dyn.QuasiStatic)",
                                "spatial.rnea(m, Q, None, A, dyn=spatial.Dyn.QuasiStatic, threads=1)"),
                               ("spatial.rnea(m, Q, None, None, dyn=Dyn.Static)",
                                "spatial.rnea(m, Q, None, None, dyn=spatial.Dyn.Static, threads=1)"),
                               ("spatial.gravity(m, Q)", "spatial.gravity(m, Q, threads=1)"),
                               ("spatial.aba(m, Q, None, T, dyn=Dyn.Static)",
                                "spatial.aba(m, Q, None, T, dyn=spatial.Dyn.Static, threads=1)")):
                add(size, "spatial", call, 1, measure(stmt, benv, **kw))
        if size == sizes[0]:  # checks, on the smaller batch
            r1 = np.asarray(spatial.rnea(stance, Q, V, A, threads=1))
            r0 = np.asarray(spatial.rnea(stance, Q, V, A, threads=0))
            checks["rnea_threads0_equals_threads1"] = bool(np.array_equal(r0, r1))
            a1_ = np.asarray(spatial.aba(stance, Q, V, T, threads=1))
            a0_ = np.asarray(spatial.aba(stance, Q, V, T, threads=0))
            checks["aba_threads0_equals_threads1"] = bool(np.array_equal(a0_, a1_))
            k = min(size, 16)
            single = np.array([spatial.rnea(stance, Q[i], V[i], A[i]) for i in range(k)])
            checks["rnea_batch_row_vs_one_call_max_abs_diff"] = float(np.abs(single - r1[:k]).max())
            rl = lanes[1].rnea(Q, V, A)
            checks["batch_lanes_rnea_max_rel_diff_from_rnea"] = float(
                np.max(np.abs(rl - r1).max(axis=1) / np.maximum(1.0, np.abs(r1).max(axis=1))))
            checks["batch_lanes_threads0_equals_threads1"] = bool(np.array_equal(lanes[0].rnea(Q, V, A), rl))
            back = np.asarray(spatial.aba(stance, Q, V, r1))
            checks["aba_of_rnea_max_abs_error_qdd"] = float(np.abs(back - A).max())
        # Python loops: measured at loop_size states, extrapolated beyond
        if size <= loop_size:
            m = measure("spatial_rnea_loop(m, Q, V, A)", benv, repeats=batch_repeats, min_time=batch_min_time)
            loop_per_state["spatial.rnea"] = (m, size)
            add(size, "spatial", "Python loop over spatial.rnea", 1, m)
        elif "spatial.rnea" in loop_per_state:
            m0, s0 = loop_per_state["spatial.rnea"]
            add(size, "spatial", "Python loop over spatial.rnea", 1, scale(m0, size / s0), extrapolated_from=s0)
        if pin is None:
            continue
        # v, q̈, τ do not depend on the model (nv = 21 for both): the same arrays; q within Pinocchio's joint order
        pQ, pV, pA, pT = random_states(rng, pmodel.lowerPositionLimit, pmodel.upperPositionLimit, pmodel.nv, size,
                                       qonly=True) + (V, A, T)
        penv = {"pin": pin, "pm": pmodel, "pd": pdata, "Q": pQ, "V": pV, "A": pA, "T": pT, "pool": pool,
                "rnea_loop": pin_rnea_loop, "aba_loop": pin_aba_loop,
                # states as columns (Eigen's column-major layout): the transposes, F-contiguous, no copy
                "Qc": pQ.T, "Vc": pV.T, "Ac": pA.T, "Tc": pT.T}
        for call, stmt in (("Python loop over pin.rnea", "rnea_loop(pin, pm, pd, Q, V, A)"),
                           ("Python loop over pin.aba", "aba_loop(pin, pm, pd, Q, V, T)")):
            if size <= loop_size:
                m = measure(stmt, penv, repeats=batch_repeats, min_time=batch_min_time)
                loop_per_state[call] = (m, size)
                add(size, "pinocchio", call, 1, m)
            elif call in loop_per_state:
                m0, s0 = loop_per_state[call]
                add(size, "pinocchio", call, 1, scale(m0, size / s0), extrapolated_from=s0)
        if pin_batch_api:
            # ~5 s per call at 1e6 states: there, one run on all cores only (one thread: see the smaller batch)
            pkw = {"repeats": 1, "number": 1} if size >= big else kw
            pthreads = (threads_all,) if size >= big else (1, threads_all)
            for call, stmt in (("pin.rneaInParallel", "pin.rneaInParallel({th}, pool, Qc, Vc, Ac)"),
                               ("pin.abaInParallel", "pin.abaInParallel({th}, pool, Qc, Vc, Tc)")):
                for th in pthreads:
                    add(size, "pinocchio", call, th, measure(stmt.format(th=th), penv, **pkw))
            if size == sizes[0]:
                tb = np.asarray(pin.rneaInParallel(threads_all, pool, penv["Qc"], penv["Vc"], penv["Ac"])).T
                tl = pin_rnea_loop(pin, pmodel, pdata, pQ, pV, pA)
                checks["pinocchio_batch_vs_loop_max_abs_diff"] = float(np.abs(tb - tl).max())
        del Q, V, A, T, benv, penv
        gc.collect()

    # --- the walking generator: one call of spatial.walk (the default 8-step walk), its stages' own clocks -----------
    t0 = time.perf_counter()
    wk = spatial.walk(steps=2 if args.quick else 8)
    walk = {"steps": 2 if args.quick else 8, "seconds_wall": time.perf_counter() - t0,
            "ticks": int(wk["open_loop_summary"]["ticks"]),
            "open_loop_seconds": float(sum(p["seconds"] for p in wk["open_loop_summary"]["passes"])),
            "passes": len(wk["open_loop_summary"]["passes"]),
            "tick_us_mean": wk["open_loop_summary"]["tick_seconds_mean"] * 1e6,
            "closed_loop_seconds": wk["closed_loop_summary"]["seconds"],
            "simulation_step_us": wk["closed_loop_summary"]["step_seconds_mean"] * 1e6,
            "walked": bool(wk["closed_loop_summary"]["walked"])}
    print(f"  spatial.walk(steps={walk['steps']}): {walk['seconds_wall']:.3g} s, walked {walk['walked']}", flush=True)
    del wk

    # --- output ---------------------------------------------------------------------------------------------------
    versions = {"python": platform.python_version(), "numpy": np.__version__,
                "spatial": getattr(spatial, "__version__", None) or distribution_version("spatial"),
                "pinocchio": getattr(pin, "__version__", None) if pin is not None else None}
    result = {
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "machine": {"cpu": cpu_model(), "logical_cpus": os.cpu_count(), "threads_all": threads_all,
                    "load_average_start": load_start,
                    "load_average_end": list(os.getloadavg()) if hasattr(os, "getloadavg") else None},
        "versions": versions,
        "quick": args.quick,
        "model": {"spatial": "hoap3_stance_right (stance21: R_SOLE root, head and wrists locked; compile-time tree) "
                             "and load_urdf of the same (run-time tree)",
                  "pinocchio": "buildModelFromUrdf(hoap3.urdf) + buildReducedModel(head and wrists locked at 0), "
                               "rooted at base_link (fine for timing: same joints and bodies)",
                  "nv": n},
        "time_statistic": "per call: median over repeats of the CPU (process) time of a timeit loop of the same call "
                          "on the same state, divided by its length; batches: median over repeats of the wall time "
                          "of one batch call (states per second of wall time)",
        "per_call": per_call,
        "cpp_source": cpp_source,
        "batch": batch,
        "pinocchio_batch_api": pin_batch_api or ("not available" if pin is not None else "absent (no pin)"),
        "checks": checks,
        "walk": walk,
        "notes": notes,
        "seconds_total": time.perf_counter() - start,
    }
    with open(os.path.join(args.out, "bench.json"), "w") as f:
        json.dump(result, f, indent=1)
    with open(os.path.join(args.out, "bench.md"), "w") as f:
        f.write(markdown(result, find_call, threads_all))
    print(f"python_bench.py: {result['seconds_total']:.1f} s; wrote {os.path.join(args.out, 'bench.json')} and "
          f"bench.md")
    return 0


def scale(m, factor):
    """A measurement of a loop scaled to `factor` times as many states (extrapolation)."""
    return dict(m, cpu_ns=m["cpu_ns"] * factor, wall_ns=m["wall_ns"] * factor, cpu_ns_min=m["cpu_ns_min"] * factor,
                wall_ns_min=m["wall_ns_min"] * factor)


def markdown(result, find_call, threads_all):
    out = []
    w = out.append
    v, mach = result["versions"], result["machine"]
    w(f"`bench/python_bench.py{' --quick' if result['quick'] else ''}`, {result['date']}: spatial "
      f"{v['spatial'] or '?'}, numpy {v['numpy']}, Pinocchio {v['pinocchio'] or 'absent'} (pip `pin`), Python "
      f"{v['python']}; {mach['cpu']}, {mach['logical_cpus']} logical CPUs, load average (1, 5, 15 min) "
      f"{', '.join(f'{x:.2f}' for x in mach['load_average_start'] or [])} at the start, "
      f"{', '.join(f'{x:.2f}' for x in mach['load_average_end'] or [])} at the end. Model: stance21 (HOAP-3 on the "
      f"right sole, {result['model']['nv']} joints); Pinocchio's from `buildModelFromUrdf` + `buildReducedModel` (the "
      "same joints locked), rooted at base_link instead of R_SOLE, which does not matter for timing.")
    w("")
    compilers = sorted({c for r in result["per_call"] for c in (r["cpp_ns_per_call"] or {})},
                       key=lambda c: ({"gcc": 0, "clang": 1}.get(c, 2), c))
    source = f"from `{result['cpp_source']}`" if result["cpp_source"] else "**missing** (no benchmark output)"
    w("**One call from Python** (the same state every call; median over repeats of the CPU time per call of a "
      "timeit loop). C++: the same call in the main job's Google Benchmark run (median CPU time, a pool of 256 "
      f"states), {source}. Pinocchio in C++ is bench_pinocchio's header-only build of the same version at -O3 "
      "-march=native, on a model converted from our stance21 (rooted at R_SOLE), not the wheel's library that `pin` "
      "calls: its difference is not Python's overhead alone.")
    w("")
    rows = []
    for r in result["per_call"]:
        cpp = r["cpp_ns_per_call"] or {}
        row = [f"`{r['call']}`", r["what"], fmt_ns(r["ns_per_call_cpu"])]
        row.append(" / ".join(fmt_ns(cpp.get(c)) for c in compilers) if compilers else "missing")
        row.append(" / ".join(fmt_delta(r["ns_per_call_cpu"] - cpp[c]) if c in cpp else "–" for c in compilers)
                   if compilers else "–")
        row.append(" / ".join(f"{r['ns_per_call_cpu'] / cpp[c]:.3g}" if c in cpp else "–" for c in compilers)
                   if compilers else "–")
        rows.append(row)
    cc = " / ".join(compilers) if compilers else ""
    w(md_table(["call", "model", "from Python", f"C++ {cc}".strip(), f"Python − C++ {cc}".strip(),
                f"Python ÷ C++ {cc}".strip()], rows))
    w("")
    ratios = []
    for algorithm in ("RNEA", "ABA"):
        s, p = find_call("spatial", algorithm, "compile"), find_call("pinocchio", algorithm, "Pinocchio")
        if s and p:
            ratios.append(f"{algorithm} {s['ns_per_call_cpu'] / p['ns_per_call_cpu']:.3g}")
    if ratios:
        w("From Python, spatial (compile-time tree) ÷ Pinocchio per call: " + ", ".join(ratios) + ".")
        w("")
    w(f"**Batches** (q within the URDF limits, v, q̈, τ uniform in [−1, 1]; (B, 21) float64 arrays; wall time, "
      f"median over repeats; threads all = `threads=0` for spatial, {threads_all} for Pinocchio). Python loops over B "
      "states are measured on the smaller batch and *extrapolated* to the larger (marked). Pinocchio's batch API: "
      f"{result['pinocchio_batch_api']}" + (" (states as columns; at 1e6 states one run, on all cores only)"
                                            if result["pinocchio_batch_api"].startswith("pin.") else "") + ".")
    w("")
    rows = []
    sizes = sorted({r["states"] for r in result["batch"]})
    for size in sizes:
        ref = next((r for r in result["batch"] if r["states"] == size and r["call"] == "Python loop over pin.rnea"),
                   None)
        refa = next((r for r in result["batch"] if r["states"] == size and r["call"] == "Python loop over pin.aba"),
                    None)
        for r in (r for r in result["batch"] if r["states"] == size):
            # a Dyn flag set or G alone computes less than the full algorithm: no "same algorithm" to compare with
            partial = "dyn=" in r["call"] or "gravity" in r["call"]
            base = None if partial else refa if "aba" in r["call"] else ref
            speedup = f"{base['ns_per_state_wall'] / r['ns_per_state_wall']:.3g}×" if base else "–"
            threads = f"all ({r['threads']})" if r["threads_argument"] == 0 else r["threads"]
            rows.append([fmt_states(size), f"`{r['call']}`", threads,
                         fmt_ns(r["seconds_per_batch_wall"] * 1e9) + (" (extrapolated)" if r["extrapolated"] else ""),
                         fmt_ns(r["ns_per_state_wall"]), fmt_rate(r["states_per_second_wall"]),
                         fmt_rate(r["states_per_second_wall_best"]) if r["repeats"] > 1 else "–", speedup,
                         r["repeats"]])
    w(md_table(["states", "call", "threads", "time per batch", "per state", "states per second",
                "best repeat", "speed-up over a Python loop of pin (same algorithm)", "repeats"], rows))
    w("")
    ch = result["checks"]
    if ch:
        w("Checks: " + "; ".join(f"{k.replace('_', ' ')}: {v if isinstance(v, bool) else f'{v:.1e}'}"
                                 for k, v in ch.items()) + ".")
        w("")
    wk = result.get("walk")
    if wk:
        w(f"**The walking generator from Python**: `spatial.walk(steps={wk['steps']})` ({wk['ticks']} ticks of 2 ms, "
          f"{'walked' if wk['walked'] else 'did NOT walk'}) took {wk['seconds_wall']:.3g} s of wall time: the open loop "
          f"{wk['open_loop_seconds']:.3g} s ({wk['passes']} passes; last pass {wk['tick_us_mean']:.3g} µs per tick: "
          f"IK, inverse dynamics with contacts, ZMP), the closed-loop simulation {wk['closed_loop_seconds']:.3g} s "
          f"({wk['simulation_step_us']:.3g} µs per 1 ms step); the rest: the plan, the preview gains, the model and the NumPy arrays.")
        w("")
    for note in result["notes"]:
        w(f"- {note}")
    if result["notes"]:
        w("")
    return "\n".join(out)


if __name__ == "__main__":
    sys.exit(main())
