"""Tests of targets_table.py: each target is read from its column and judged against its bound."""
import contextlib
import io
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import targets_table  # noqa: E402

HEADER = ("| scan | points | image | markers | read | project | preprocess | detect | lift | pose "
          "| total (no read) | Mpoints/s | floor | project / floor | total / floor |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")


def bench_row(scan, total, project_over_floor):
    return (f"| {scan} | 1000 | 10x10 | 1 | 0.1 (0.1-0.1) | 1.0 (1.0-1.1) | 1.0 (1.0-1.0) "
            f"| 1.0 (1.0-1.0) | 1.0 (1.0-1.0) | 0.0 (0.0-0.0) | {total} | 1.0 | 0.5 "
            f"| {project_over_floor} | 9.9 |\n")


def google_benchmark(medians):
    return {"benchmarks": [{"run_name": name, "aggregate_name": "median", "real_time": ms,
                            "cpu_time": ms} for name, ms in medians.items()]}


class TargetsTable(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def write(self, name, text):
        path = os.path.join(self.dir.name, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def table(self, one, two, *extra):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            targets_table.main([self.write("one.md", one), self.write("two.md", two), *extra])
        return {line.split("|")[1].strip(): [c.strip() for c in line.strip().strip("|").split("|")]
                for line in out.getvalue().splitlines()[2:]}

    def test_each_target_is_judged_on_its_own_median(self):
        one = "iilfm bench: ...\n\n" + HEADER + bench_row("mid40-60", "6.10 (6.0-6.3)", "2.5") + \
            bench_row("vlp16", "0.48 (0.45-0.52)", "9.0") + bench_row("ultrapuck", "1.20 (1.1-1.3)", "9.0")
        two = HEADER + bench_row("mid40-60", "4.90 (4.8-5.1)", "2.0") + \
            bench_row("vlp16", "0.47 (0.45-0.50)", "9.0") + bench_row("ultrapuck", "1.10 (1.0-1.2)", "9.0")
        baseline = self.write("baseline.json", json.dumps(google_benchmark(
            {"PaperBaseline/mid40-60": 200.0, "Iilfm/mid40-60": 6.0,
             "PaperBaseline/vlp16": 2.0, "Iilfm/vlp16": 0.5})))
        window = self.write("window.json", json.dumps(google_benchmark(
            {"WindowPush/mid40-60/mode:2": 2.5, "WindowPush/mid40-60/mode:3": 1.9})))
        rows = self.table(one, two, "--baseline", baseline, "--window", window)
        mid40, vlp16, puck = (rows[k] for k in ("Mid-40, 60 frames (`mid40-60`), end to end",
                                                "VLP-16 sweep (`vlp16`), end to end",
                                                "32-ring sweep (`ultrapuck`), end to end"))
        self.assertEqual(mid40[2:], ["6.10 ms (6.0-6.3)", "4.90 ms (4.8-5.1)", "with two threads"])
        self.assertEqual(vlp16[2:], ["0.48 ms (0.45-0.52)", "0.47 ms (0.45-0.50)", "yes"])
        self.assertEqual(puck[4], "no")
        streaming = next(v for k, v in rows.items() if k.startswith("streaming"))
        self.assertEqual(streaming[2:], ["2.50 ms", "1.90 ms", "with two threads"])
        by_baseline = {k: v for k, v in rows.items() if "paper baseline" in k}
        self.assertEqual(by_baseline["faster than the paper baseline, `mid40-60`"][2:], ["33.33x", "-", "yes"])
        self.assertEqual(by_baseline["faster than the paper baseline, `vlp16`"][2:], ["4.00x", "-", "no"])
        self.assertEqual(rows["projection over the floor, `mid40-60`"][2:], ["2.50x", "2.00x", "yes"])

    def test_a_target_not_measured_is_never_met(self):
        rows = self.table(HEADER + bench_row("vlp16", "0.40 (0.4-0.4)", "1.0"), HEADER)
        self.assertEqual(rows["VLP-16 sweep (`vlp16`), end to end"][2:], ["0.40 ms (0.4-0.4)", "-", "yes"])
        self.assertEqual(rows["Mid-40, 60 frames (`mid40-60`), end to end"][4], "not measured")
        self.assertEqual(rows["faster than the paper baseline, `vlp16`"][4], "not measured")


if __name__ == "__main__":
    unittest.main()
