#!/usr/bin/env python3
"""Tables and goal figures from a loosehair_bench JSON file.

    build/release/benchmarks/loosehair_bench --benchmark_repetitions=5 \\
        --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true \\
        --benchmark_filter='Step|Neighbor|Density|Memory' \\
        --benchmark_out=bench.json --benchmark_out_format=json
    benchmarks/summarize.py bench.json

Prints, for the median and for the lowest of the repetitions ("min"), the
README's table (milliseconds a call), the two-thread speed-up of the full
step at each N, the exponent p of time ~ N^p from 10k to 200k particles, and
the memory bandwidth with 1 and 2 threads. Needs the aggregates, so the run
must have repetitions.
"""
import json
import math
import sys


def load(path):
    with open(path) as f:
        data = json.load(f)
    out = {}  # (family, particles, threads, aggregate) -> benchmark entry
    for b in data["benchmarks"]:
        agg = b.get("aggregate_name")
        if agg not in ("median", "min"):
            continue
        parts = b["run_name"].split("/")
        fields = dict(p.split(":", 1) for p in parts[1:] if ":" in p)
        family = parts[0]
        if "particles" in fields:
            key = (family, int(fields["particles"]), int(fields["threads"]), agg)
        elif "threads" in fields:
            key = (family, 0, int(fields["threads"]), agg)
        else:
            continue
        out[key] = b
    return out


def ms(b):
    unit = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
    return b["real_time"] * unit


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: summarize.py BENCH.json")
    runs = load(sys.argv[1])
    counts = sorted({k[1] for k in runs if k[0] == "BM_Step"})
    for agg in ("median", "min"):
        def get(family, n, threads):
            b = runs.get((family, n, threads, agg))
            return ms(b) if b else float("nan")

        print(f"\n{agg}:\n")
        print("| N | neighbour search 1 / 2 thr | density 1 / 2 thr | full step 1 / 2 thr "
              "| speed-up | M p-steps/s (2 thr) |")
        print("| ---: | ---: | ---: | ---: | ---: | ---: |")
        for n in counts:
            nb1, nb2 = get("BM_NeighborSearch", n, 1), get("BM_NeighborSearch", n, 2)
            d1, d2 = get("BM_Density", n, 1), get("BM_Density", n, 2)
            s1, s2 = get("BM_Step", n, 1), get("BM_Step", n, 2)
            print(f"| {n:,} | {nb1:.3g} / {nb2:.3g} ms | {d1:.3g} / {d2:.3g} ms "
                  f"| {s1:.3g} / {s2:.3g} ms | {s1 / s2:.2f}x | {n / s2 / 1e3:.1f} |")
        if 10000 in counts and 200000 in counts:
            for threads in (1, 2):
                a, b = get("BM_Step", 10000, threads), get("BM_Step", 200000, threads)
                p = math.log(b / a) / math.log(20.0)
                print(f"\nfull step, {threads} thread(s): 10k -> 200k grows as N^{p:.3f}")
        for family in ("BM_MemoryRead", "BM_MemoryCopy") if agg == "median" else ():
            b1, b2 = runs.get((family, 0, 1, agg)), runs.get((family, 0, 2, agg))
            if b1 and b2:
                g1, g2 = b1["bytes_per_second"] / 1e9, b2["bytes_per_second"] / 1e9
                print(f"{family}: {g1:.1f} / {g2:.1f} GB/s (1 / 2 threads, {g2 / g1:.2f}x)")


if __name__ == "__main__":
    main()
