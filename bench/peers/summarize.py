#!/usr/bin/env python3
"""Summarises bench/out/peers_*.csv (standard library only).

    bench/peers/summarize.py [--out DIR] [--h 1e-3]

Prints, per case, every engine/config at step size h (wall ns/step, the
thread-CPU ns/step of the same timing runs from cputime_<engine>.csv when
present, and the four errors at T = 100 s), then the observed convergence order of the orientation
error: the least-squares slope of log(err) against log(h) over the step sizes
where the run did not blow up and 1e-11 < err < 0.1 (errors near the
reference/roundoff floor or already O(1) are excluded); "-" if fewer than 3
such points.
"""
import argparse
import csv
import glob
import math
import os
from collections import defaultdict


def fnum(s):
    try:
        return float(s)
    except ValueError:
        return float("nan")


def slope(points):
    if len(points) < 3:
        return None
    xs = [math.log(h) for h, _ in points]
    ys = [math.log(e) for _, e in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx == 0:
        return None
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def median(v):
    v = sorted(x for x in v if not math.isnan(x))
    return v[len(v) // 2] if v else float("nan")


def compact(rows, cpu, cases, h):
    print(f"Orientation error (rad) at T = 100 s with h = {h:g} s; ns/step = median over the cases\n")
    print("| engine / config | ns/step wall | ns/step CPU | " + " | ".join(cases) + " |")
    print("|---|---:|---:|" + "---:|" * len(cases))
    configs = []
    for r in rows:
        if (r["engine"], r["config"]) not in configs:
            configs.append((r["engine"], r["config"]))
    for eng, cfg in configs:
        sel = [r for r in rows if r["engine"] == eng and r["config"] == cfg
               and math.isclose(fnum(r["h"]), h, rel_tol=1e-9)]
        if not sel:
            continue
        wall = median([fnum(r["ns_per_step"]) for r in sel])
        c = median([cpu.get((eng, cfg, r["case"], fnum(r["h"])), float("nan")) for r in sel])
        cells = []
        for case in cases:
            rr = [r for r in sel if r["case"] == case]
            if not rr:
                cells.append("")
            elif rr[0]["blew_up"] == "1":
                cells.append("blew up")
            else:
                cells.append(f"{fnum(rr[0]['err_orientation_rad']):.2e}")
        fmt = lambda x: "-" if math.isnan(x) else f"{x:.0f}"
        print(f"| {eng} {cfg} | {fmt(wall)} | {fmt(c)} | " + " | ".join(cells) + " |")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(here, "..", "out"))
    ap.add_argument("--h", type=float, default=1e-3)
    ap.add_argument("--compact", action="store_true",
                    help="one table: orientation error per case, ns/step as the median over the cases")
    args = ap.parse_args()

    rows = []
    for path in sorted(glob.glob(os.path.join(args.out, "peers_*.csv"))):
        with open(path) as f:
            rows.extend(r for r in csv.DictReader(f) if r.get("blew_up") in ("0", "1"))
    if not rows:
        print("no peers_*.csv in", args.out)
        return

    cpu = {}
    for path in glob.glob(os.path.join(args.out, "cputime_*.csv")):
        with open(path) as f:
            for r in csv.DictReader(f):
                try:
                    cpu[(r["engine"], r["config"], r["case"], float(r["h"]))] = float(r["cpu_ns_per_step"])
                except (KeyError, TypeError, ValueError):
                    pass

    cases = []
    for r in rows:
        if r["case"] not in cases:
            cases.append(r["case"])

    if args.compact:
        compact(rows, cpu, cases, args.h)
        return

    print(f"## Step size h = {args.h:g} s, errors at T = 100 s\n")
    for case in cases:
        print(f"### {case}\n")
        print("| engine | config | ns/step (wall) | ns/step (CPU) | orientation (rad) | CoM (m) | energy (rel) | abs(L) (rel) |")
        print("|---|---|---:|---:|---:|---:|---:|---:|")
        for r in rows:
            if r["case"] != case or not math.isclose(fnum(r["h"]), args.h, rel_tol=1e-9):
                continue
            ns = fnum(r["ns_per_step"])
            ns_s = "-" if math.isnan(ns) else f"{ns:.0f}"
            c = cpu.get((r["engine"], r["config"], r["case"], fnum(r["h"])), float("nan"))
            cpu_s = "-" if math.isnan(c) else f"{c:.0f}"
            if r["blew_up"] == "1":
                errs = ["blew up", "", "", ""]
            else:
                errs = [f"{fnum(r[k]):.2e}" for k in
                        ("err_orientation_rad", "err_com_m", "err_energy_rel", "err_L_rel")]
            print(f"| {r['engine']} | {r['config']} | {ns_s} | {cpu_s} | " + " | ".join(errs) + " |")
        print()

    print("## Observed order of the orientation error (slope of log err vs log h)\n")
    pts = defaultdict(list)
    for r in rows:
        e = fnum(r["err_orientation_rad"])
        if r["blew_up"] == "0" and 1e-11 < e < 0.1:
            pts[(r["engine"], r["config"], r["case"])].append((fnum(r["h"]), e))
    configs = []
    for r in rows:
        k = (r["engine"], r["config"])
        if k not in configs:
            configs.append(k)
    print("| engine | config | " + " | ".join(cases) + " |")
    print("|---|---|" + "---:|" * len(cases))
    for eng, cfg in configs:
        cells = []
        for case in cases:
            s = slope(pts.get((eng, cfg, case), []))
            cells.append("-" if s is None else f"{s:.2f}")
        print(f"| {eng} | {cfg} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
