#!/usr/bin/env python3
"""Markdown tables of examples/README.md's laser section from bench_laser_planners' JSON.

Usage: build/benchmarks/bench_laser_planners > bench.json; python3 tools/laser-planner-table.py bench.json
"""
import json
import sys

r = json.load(open(sys.argv[1]))
l = r["l_part_2mm"]
s = l["sse_mJ2_per_mm4"]
print("| plan | SSE (mJ^2/mm^4) | / ACES 5% | / ACES cure-at-contour |")
print("|---|---|---|---|")
for label, key in [("ACES, seed 5% edge rule", "aces_5_percent"),
                   ("ACES, cure-at-contour", "aces_cure_at_contour"),
                   ("DFBTP", "dfbtp"),
                   ("inverse, exposure-l2 (40 coarse + 30 fine iterations)", "inverse")]:
    print(f"| {label} | {s[key]:.1f} | {s[key] / s['aces_5_percent']:.2f} | "
          f"{s[key] / s['aces_cure_at_contour']:.2f} |")
print()
names = {"aces": "aces", "dfbtp": "dfbtp", "dfbtp_shape_edges": "dfbtp (edges: shape)",
         "inverse_shape": "inverse (shape)",
         "inverse_exposure_l2": "inverse (exposure-l2)"}
print("| job | strategy | IoU | mean / RMS deviation (um) | over-cure below down-facing, "
      "mean / median (um) | build time (s) | plan (s) |")
print("|---|---|---|---|---|---|---|")
for job, strategies in r["examples"].items():
    first = True
    for key, label in names.items():
        if key not in strategies:
            continue
        e = strategies[key]
        print(f"| {job if first else ''} | {label} | {e['iou']:.4f} | "
              f"{e['mean_deviation_um']:+.1f} / {e['rms_deviation_um']:.1f} | "
              f"{e['overcure_below_downfacing_mean_um']:.1f} / "
              f"{e['overcure_below_downfacing_median_um']:.0f} | "
              f"{e.get('build_time_s', float('nan')):.4g} | {e['plan_seconds']:.1f} |")
        first = False
print()
print("Targets:", ", ".join(
    f"{job}: " + " ".join(f"{k}={'yes' if v else 'NO'}" for k, v in t.items())
    if isinstance(t, dict) else f"{job}={'yes' if t else 'NO'}"
    for job, t in r["targets"].items()))
print(f"(load average {r['load_average_1min']:.1f} on {r['cores']} cores)")
