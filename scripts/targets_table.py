"""Issue 8's speed targets against one perf_report run -> a Markdown table with a "met" column.

Usage: targets_table.py BENCH_1_THREAD.md BENCH_2_THREADS.md [--baseline JSON] [--window JSON]
The bench files are `iilfm bench --markdown` outputs; --baseline is iilfm_bench_baseline's and
--window iilfm_bench_stages' (WindowPush/mid40-60) Google Benchmark JSON. A target whose figures
were not measured in the run is listed as such, never as met.
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from baseline_table import baseline_medians  # noqa: E402


def bench_rows(path):
    """{scan: {column: median}} from an `iilfm bench --markdown` table."""
    header, rows = None, {}
    with open(path) as f:
        lines = f.readlines()
    for line in lines:
        if not line.startswith("|") or line.startswith("|---"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if header is None:
            header = cells
            continue
        rows[cells[0]] = dict(zip(header, cells))
    return rows


def window_medians(path):
    """{mode: median ms} of WindowPush/mid40-60/mode:N."""
    medians = {}
    with open(path) as f:
        runs = json.load(f)["benchmarks"]
    for b in runs:
        if b.get("aggregate_name") == "median" and b["run_name"].startswith("WindowPush/mid40-60/"):
            medians[int(b["run_name"].rsplit(":", 1)[1])] = b["real_time"]
    return medians


def main(argv):
    parser = argparse.ArgumentParser()
    parser.add_argument("one_thread")
    parser.add_argument("two_threads")
    parser.add_argument("--baseline")
    parser.add_argument("--window")
    args = parser.parse_args(argv)
    one, two = bench_rows(args.one_thread), bench_rows(args.two_threads)
    ratios = {}
    if args.baseline:
        with open(args.baseline) as f:
            runs = json.load(f)["benchmarks"]
        for scan, m in baseline_medians(runs).items():
            if "PaperBaseline" in m and "Iilfm" in m:
                ratios[scan] = m["PaperBaseline"][0] / m["Iilfm"][0]
    window = window_medians(args.window) if args.window else {}

    # A bench cell, "9.25 (8.97-9.54)": its median, and its spread (10th-90th percentile) if any.
    def bench(rows, scan, column):
        cell = rows.get(scan, {}).get(column)
        if not cell:
            return None
        median, _, spread = cell.partition(" ")
        return float(median), spread

    def measured(value):
        return None if value is None else (value, "")

    # (target, bound, at most?, one thread, two threads, unit); figures are (median, spread).
    targets = [
        ("Mid-40, 60 frames (`mid40-60`), end to end", 5.0, True,
         bench(one, "mid40-60", "total (no read)"), bench(two, "mid40-60", "total (no read)"), "ms"),
        ("VLP-16 sweep (`vlp16`), end to end", 0.5, True,
         bench(one, "vlp16", "total (no read)"), bench(two, "vlp16", "total (no read)"), "ms"),
        ("32-ring sweep (`ultrapuck`), end to end", 1.0, True,
         bench(one, "ultrapuck", "total (no read)"), bench(two, "ultrapuck", "total (no read)"),
         "ms"),
        ("streaming Mid-40, 60-frame window, a push (`WindowPush/mid40-60`, mode 2; 3 on two)",
         2.0, True, measured(window.get(2)), measured(window.get(3)), "ms"),
        ("faster than the paper baseline, `mid40-60`", 5.0, False, measured(ratios.get("mid40-60")),
         None, "x"),
        ("faster than the paper baseline, `vlp16`", 5.0, False, measured(ratios.get("vlp16")), None,
         "x"),
        ("projection over the floor, `mid40-60`", 3.0, True, bench(one, "mid40-60", "project / floor"),
         bench(two, "mid40-60", "project / floor"), "x"),
    ]
    print("| target | bound | one thread | two threads | met |")
    print("|---|---|---|---|---|")

    def number(value, unit):
        return f"{value:.2f}{unit}" if unit == "x" else f"{value:.2f} {unit}"

    def shown(figure, unit):
        if figure is None:
            return "not measured"
        median, spread = figure
        return number(median, unit) + (f" {spread}" if spread else "")

    def meets(figure, bound, at_most):
        return figure is not None and (figure[0] <= bound if at_most else figure[0] >= bound)

    for name, bound, at_most, one_thread, two_threads, unit in targets:
        if one_thread is None:
            met = "not measured"
        elif meets(one_thread, bound, at_most):
            met = "yes"
        else:
            met = "with two threads" if meets(two_threads, bound, at_most) else "no"
        two_text = shown(two_threads, unit) if two_threads is not None else "-"
        sign = "<=" if at_most else ">="
        print(f"| {name} | {sign} {number(bound, unit)} | {shown(one_thread, unit)} | {two_text} "
              f"| {met} |")


if __name__ == "__main__":
    main(sys.argv[1:])
