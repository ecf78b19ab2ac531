#!/usr/bin/env python3
"""How much a ratio to a peer moves from one run of the benchmarks to the next, with the two ways scripts/main.sh can
run them: one binary after the other, all repetitions in one run each ("sequential", ROUNDS=1), or in rounds (each
binary once per round with one repetition, the binaries of a round in random order; main.sh's default).

    tools/ratio_spread.py OURS PEER [--trials 6] [--repetitions 5] [--filter REGEX] [--min-time 0.05]

OURS and PEER are benchmark binaries (e.g. build-clang/bin/bench_floating and build-clang/bin/bench_pinocchio). Each
trial runs both schemes, in alternating order, and takes the ratio spatial ÷ peer of every benchmark the two binaries
share (same algorithm, model and scalar; spatial's compile-time tree) from the medians tools/report.py computes. Prints,
per benchmark and scheme, the ratios of the trials and their largest ÷ smallest value, then the mean of that spread."""

import argparse
import os
import random
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report  # noqa: E402


def run(binary, out, repetitions, args):
    subprocess.run([binary, f"--benchmark_min_time={args.min_time}", f"--benchmark_repetitions={repetitions}",
                    "--benchmark_enable_random_interleaving=true", "--benchmark_report_aggregates_only=true",
                    f"--benchmark_filter={args.filter}", f"--benchmark_out={out}", "--benchmark_out_format=json"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def ratios(files):
    """{(algorithm, model, scalar): spatial ÷ peer} from {binary: [json files]}."""
    times = {}
    for paths in files.values():
        times.update(report.read_benchmark_files(paths, "cpu")[1])
    out = {}
    for (impl, algorithm, model, scalar, tree), ns in times.items():
        if impl != "spatial" or tree != "static":
            continue
        for peer in ("pinocchio", "kdl"):
            p = times.get((peer, algorithm, model, scalar, "-"))
            if p:
                out[(algorithm, model, scalar)] = ns / p
    return out


def trial(binaries, scheme, tmp, k, args):
    files = {b: [] for b in binaries}
    if scheme == "sequential":
        for b in binaries:
            path = os.path.join(tmp, f"{k}-{scheme}-{os.path.basename(b)}.json")
            run(b, path, args.repetitions, args)
            files[b].append(path)
    else:
        for r in range(args.repetitions):
            for b in random.sample(binaries, len(binaries)):
                path = os.path.join(tmp, f"{k}-{scheme}-{os.path.basename(b)}.round{r}.json")
                run(b, path, 1, args)
                files[b].append(path)
    return ratios(files)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("ours")
    ap.add_argument("peer")
    ap.add_argument("--trials", type=int, default=6)
    ap.add_argument("--repetitions", type=int, default=5)
    ap.add_argument("--filter", default=".")
    ap.add_argument("--min-time", default="0.05")
    args = ap.parse_args()
    binaries = [args.ours, args.peer]
    results = {"sequential": [], "rounds": []}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.trials):
            schemes = ["sequential", "rounds"] if k % 2 == 0 else ["rounds", "sequential"]
            for scheme in schemes:
                results[scheme].append(trial(binaries, scheme, tmp, k, args))
                print(f"trial {k + 1}/{args.trials} {scheme} done", file=sys.stderr)
    keys = sorted(set.intersection(*(set(r) for rs in results.values() for r in rs)))
    spreads = {s: [] for s in results}
    print(f"{'benchmark':42} {'scheme':10} {'largest÷smallest':>16}  ratios of the trials")
    for key in keys:
        for scheme, rs in results.items():
            values = [r[key] for r in rs]
            spread = max(values) / min(values)
            spreads[scheme].append(spread)
            print(f"{'/'.join(key):42} {scheme:10} {spread:16.3f}  " + " ".join(f"{v:.3f}" for v in values))
    for scheme, s in spreads.items():
        if s:
            print(f"mean largest÷smallest over {len(s)} ratios, {scheme}: {sum(s) / len(s):.3f} (max {max(s):.3f})")


if __name__ == "__main__":
    main()
