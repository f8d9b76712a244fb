#!/usr/bin/env python3
"""Markdown tables from bench/out/contacts_<engine>.csv (peer contact benchmark).

    bench/peers/summarize_contacts.py [--out DIR] [--h 0.001]

Table 1: every error metric per engine/config at one step size (default 1 ms).
Table 2: ns per step (wall | thread CPU) per case at that step size.
Table 3: each metric over all step sizes found (h columns), compact.
"""
import argparse
import csv
import glob
import math
import os

here = os.path.dirname(os.path.abspath(__file__))
ap = argparse.ArgumentParser()
ap.add_argument("--out", default=os.path.join(here, "..", "out"))
ap.add_argument("--h", type=float, default=1e-3)
args = ap.parse_args()

rows, cpu = [], {}
for path in sorted(glob.glob(os.path.join(args.out, "contacts_*.csv"))):
    with open(path) as f:
        rows += list(csv.DictReader(f))
for path in sorted(glob.glob(os.path.join(args.out, "cpu_contacts_*.csv"))):
    with open(path) as f:
        for r in csv.DictReader(f):
            cpu[(r["engine"], r["config"], r["case"], float(r["h"]))] = float(r["cpu_ns_per_step"])

case_order = ["bounce", "incline_stick", "incline_slide", "slide_stop", "rolling_sphere", "stack10", "pile1000"]
metrics = []  # (case, metric) in order of appearance, sorted by case order
for r in rows:
    k = (r["case"], r["error_metric"])
    if k not in metrics and r["error_metric"] != "crashed":
        metrics.append(k)
metrics.sort(key=lambda k: case_order.index(k[0]) if k[0] in case_order else 99)
configs = []
for r in rows:
    k = (r["engine"], r["config"])
    if k not in configs:
        configs.append(k)


def fmt(v):
    v = float(v)
    if math.isinf(v):
        return "inf"
    if v == int(v) and abs(v) < 1e4:
        return "%d" % v
    return "%.2e" % v


def val(eng, cfg, case, metric, h):
    for r in rows:
        if (r["engine"], r["config"], r["case"]) == (eng, cfg, case) and abs(float(r["h"]) - h) < 1e-12:
            if r["error_metric"] == metric:
                return fmt(r["error"])
            if r["error_metric"] == "crashed":
                return "crashed"
    return "-"


print("Errors at h = %g s\n" % args.h)
print("| engine / config | " + " | ".join("%s %s" % m for m in metrics) + " |")
print("|---|" + "---:|" * len(metrics))
for eng, cfg in configs:
    print("| %s %s | " % (eng, cfg) + " | ".join(val(eng, cfg, c, m, args.h) for c, m in metrics) + " |")

print("\nns per step at h = %g s, wall / thread CPU\n" % args.h)
cases = [c for c in case_order if any(r["case"] == c for r in rows)]
print("| engine / config | " + " | ".join(cases) + " |")
print("|---|" + "---:|" * len(cases))
for eng, cfg in configs:
    cells = []
    for c in cases:
        w = [r for r in rows if (r["engine"], r["config"], r["case"]) == (eng, cfg, c) and abs(float(r["h"]) - args.h) < 1e-12]
        if not w or w[0]["ns_per_step"] in ("nan", ""):
            cells.append("-")
            continue
        cp = cpu.get((eng, cfg, c, args.h), float("nan"))
        cells.append("%.0f / %.0f" % (float(w[0]["ns_per_step"]), cp))
    print("| %s %s | " % (eng, cfg) + " | ".join(cells) + " |")

hs = sorted({float(r["h"]) for r in rows})
if len(hs) > 1:
    print("\nAll step sizes (h = %s s)\n" % ", ".join("%g" % h for h in hs))
    print("| case / metric | engine / config | " + " | ".join("h=%g" % h for h in hs) + " |")
    print("|---|---|" + "---:|" * len(hs))
    for c, m in metrics:
        if c == "pile1000":
            continue
        for eng, cfg in configs:
            print("| %s %s | %s %s | " % (c, m, eng, cfg) + " | ".join(val(eng, cfg, c, m, h) for h in hs) + " |")
