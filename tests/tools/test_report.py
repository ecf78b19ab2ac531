#!/usr/bin/env python3
"""tools/report.py's reading of Google Benchmark JSON (standard library only; ctest runs it as `report_reading`): a
benchmark's time is the median of its samples (a run's median aggregate, else its single repetitions), over one file
(scripts/main.sh: one per binary) or over several runs of a binary (tools/ratio_spread.py)."""

import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import report  # noqa: E402

KEY = ("spatial", "CRBA", "floating27", "double", "static")
PEER = ("pinocchio", "CRBA", "floating27", "double", "-")
BATCH = ("spatial", "RNEA_batch", "stance21", "double", "static", 1024, 1)
BATCH_NAME = "spatial/RNEA_batch/stance21/double/static/batch:1024/threads:1/process_time"


def single(name, cpu, real=None):
    return {"name": name, "run_name": name, "run_type": "iteration", "cpu_time": cpu,
            "real_time": cpu if real is None else real, "time_unit": "ns"}


def median(name, cpu):
    return {"name": name + "_median", "run_name": name, "run_type": "aggregate", "aggregate_name": "median",
            "cpu_time": cpu, "real_time": cpu, "time_unit": "us"}


class Reading(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.cdir = os.path.join(self.tmp.name, "gcc")
        os.makedirs(self.cdir)

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, name, benchmarks, context=None):
        path = os.path.join(self.cdir, name)
        with open(path, "w") as f:
            json.dump({"context": context or {}, "benchmarks": benchmarks}, f)
        return path

    def test_one_file_per_binary(self):
        name, peer = "/".join(KEY), "/".join(PEER)
        # the median aggregate wins over the singles written beside it; without one, the median of the singles
        self.write("bench_floating.json", [single(name, 90.0), single(name, 400.0), median(name, 0.1),
                                           single(BATCH_NAME, 9e5, 1.8e6), single(BATCH_NAME, 7e5, 1.4e6),
                                           single(BATCH_NAME, 8e5, 1.6e6)], {"binary": "floating"})
        self.write("bench_pinocchio.json", [single(peer, 50.0), single(peer, 40.0)])
        self.write("notes.txt", [])
        entry = report.read_inputs(self.tmp.name, "cpu")["gcc"]
        self.assertEqual(entry["times"][KEY], 100.0)
        self.assertEqual(entry["times"][PEER], 50.0)  # the upper median of an even count
        self.assertEqual(entry["batch_times"][BATCH], {"cpu": 8e5, "real": 1.6e6})
        self.assertEqual(sorted(entry["contexts"]), ["bench_floating", "bench_pinocchio"])
        self.assertEqual(entry["contexts"]["bench_floating"], {"binary": "floating"})

    def test_runs_of_a_binary_give_the_median_of_their_samples(self):
        name = "/".join(KEY)
        paths = [self.write(f"run{k}.json", [single(name, ns), single(BATCH_NAME, b, 2 * b)], {"run": k})
                 for k, (ns, b) in enumerate([(700.0, 9e5), (900.0, 7e5), (500.0, 8e5)], 1)]
        # a run with repetitions gives one sample, its median
        paths.append(self.write("run4.json", [single(name, 90.0), single(name, 1000.0), median(name, 0.95)]))
        paths.append(self.write("run5.json", [single(name, 600.0)]))
        context, times, batch_times = report.read_benchmark_files(paths, "cpu")
        self.assertEqual(times[KEY], 700.0)  # of 500, 600, 700, 900, 950
        self.assertEqual(batch_times[BATCH], {"cpu": 8e5, "real": 1.6e6})
        self.assertEqual(context, {"run": 1})
        self.assertEqual(report.read_benchmark_files(paths, "real")[1][KEY], 700.0)


if __name__ == "__main__":
    unittest.main()
