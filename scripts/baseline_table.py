"""Google Benchmark JSON of iilfm_bench_baseline on stdin -> a Markdown table with the ratio."""
import json
import sys


def baseline_medians(runs):
    """{scan: {method: (wall ms, CPU ms, markers)}} from the runs' median aggregates."""
    medians = {}
    for b in runs:
        if b.get("aggregate_name") != "median":
            continue
        method, scan = b["run_name"].split("/", 1)
        medians.setdefault(scan, {})[method] = (b["real_time"], b["cpu_time"],
                                                int(b.get("markers", 0)))
    return medians


def main():
    medians = baseline_medians(json.load(sys.stdin)["benchmarks"])
    print("| scan | paper approach: ms (CPU ms), markers | iilfm: ms (CPU ms), markers | iilfm faster by |")
    print("|---|---|---|---|")
    for scan, m in medians.items():
        if "PaperBaseline" not in m or "Iilfm" not in m:
            continue
        (bw, bc, bm), (iw, ic, im) = m["PaperBaseline"], m["Iilfm"]
        print(f"| {scan} | {bw:.1f} ({bc:.1f}), {bm} | {iw:.1f} ({ic:.1f}), {im} | {bw / iw:.1f}x |")


if __name__ == "__main__":
    main()
