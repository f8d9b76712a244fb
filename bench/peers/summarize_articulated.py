#!/usr/bin/python3
"""Markdown tables and one diagram from bench/out/articulated_<engine>.csv: the articulated
benchmark (doc/benchmarks-articulated.md), cga_rigid_sim (bench_articulated) beside the peers.

    bench/peers/summarize_articulated.py [--out DIR] [--h 0.001] [--clock cpu|wall] [--plot [PNG]]

Table 1, per case: every engine/config at step size h: ns per step (thread CPU and wall), the
joint-position and joint-velocity errors at T and the energy drift.
Table 2, per case: the joint-position error over the peers' step sizes, and its observed order
(least-squares slope of log err against log h over the points with 1e-12 < err < 0.1).
Table 3, per case: the cheapest run of each engine/config (CPU time per simulated second) that
reaches err_q <= 1e-3, 1e-6, 1e-9.
Table 4, the target "lower error than every peer at equal cost": per case and metric (joint
error, energy drift), how many peer points (config and h) a run of ours beats — lower error at no
greater cost per simulated second — and the worst of those it does not.
--plot: joint-position error at T and energy drift against the cost of one simulated second
(ns per step / h, thread CPU unless --clock wall; ns per step alone barely changes with h, so
it would stack each config's points on one vertical line), one column per case, gnuplot PNG
(default doc/img/articulated_work_precision.png), in the style of bench/report.py.
"""
import argparse
import csv
import glob
import math
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(os.path.dirname(here))
sys.path.insert(0, os.path.join(root, "bench"))
import report  # noqa: E402  (bench/report.py: gnuplot helpers and series styles)

ap = argparse.ArgumentParser()
ap.add_argument("--out", default=os.path.join(here, "..", "out"))
ap.add_argument("--h", type=float, default=1e-3)
ap.add_argument("--clock", choices=["cpu", "wall"], default="cpu",
                help="cost of table 3 and of the diagram (default: thread CPU time)")
ap.add_argument("--plot", nargs="?", const=os.path.join(root, "doc", "img", "articulated_work_precision.png"),
                help="draw the diagram (gnuplot) to this PNG")
args = ap.parse_args()

OURS = report.OURS
CASES = ["double_pendulum", "arm7", "satellite"]
T_OF = {"double_pendulum": 10, "arm7": 2, "satellite": 10}


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return float("nan")


rows = []
for path in sorted(glob.glob(os.path.join(args.out, "articulated_*.csv"))):
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if None in r or None in r.values():
                continue
            rows.append({"engine": r["engine"], "config": r["config"], "case": r["case"], "h": num(r["h"]),
                         "cpu": num(r["ns_per_step"]), "wall": num(r["wall_ns_per_step"]),
                         "q": num(r["err_q_rad"]), "qd": num(r["err_qd_rad_s"]),
                         "E": num(r["energy_drift_rel"]), "blew": r["blew_up"].strip() not in ("0", ""),
                         "notes": r["notes"]})
if not rows:
    sys.exit("summarize_articulated.py: no articulated_*.csv in %s" % args.out)
configs = []
for r in rows:
    k = (r["engine"], r["config"])
    if k not in configs:
        configs.append(k)
configs.sort(key=lambda k: k[0] != OURS)  # ours first, then the peers in file (engine) order
cases = [c for c in CASES if any(r["case"] == c for r in rows)] + sorted(
    {r["case"] for r in rows} - set(CASES))


def cost(r):
    return r["cpu"] if args.clock == "cpu" else r["wall"]


def fmt(v, blew=False):
    if blew:
        return "blew up"
    if v is None or math.isnan(v):
        return "–"
    if math.isinf(v):
        return "inf"
    if v < report.PLOT_FLOOR:
        return "< 1e-16"
    return "%.2e" % v


def fmt_ns(v):
    return "–" if math.isnan(v) else ("%.0f" % v if v >= 100 else "%.1f" % v)


def name(eng, cfg):
    return ("**%s %s**" if eng == OURS else "%s %s") % (eng, cfg)


def same_h(a, b):
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b))


def pick(eng, cfg, case, h):
    for r in rows:
        if (r["engine"], r["config"], r["case"]) == (eng, cfg, case) and same_h(r["h"], h):
            return r
    return None


def slope(points):
    if len(points) < 3:
        return None
    xs = [math.log(h) for h, _ in points]
    ys = [math.log(e) for _, e in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return None if sxx == 0 else sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


for case in cases:
    print("### %s: h = %g s, T = %g s\n" % (case, args.h, T_OF.get(case, float("nan"))))
    print("| engine / config | ns/step CPU | ns/step wall | joint error (rad) | velocity error (rad/s) | energy drift |")
    print("|---|---:|---:|---:|---:|---:|")
    for eng, cfg in configs:
        r = pick(eng, cfg, case, args.h)
        if r is None:
            continue
        print("| %s | %s | %s | %s | %s | %s |" % (name(eng, cfg), fmt_ns(r["cpu"]), fmt_ns(r["wall"]),
                                                   fmt(r["q"], r["blew"]), fmt(r["qd"], r["blew"]),
                                                   fmt(r["E"], r["blew"])))
    print()

for case in cases:
    # The peers' step sizes (ours may also have run at others, between them: table 4 uses those).
    hs = sorted({r["h"] for r in rows if r["case"] == case and r["engine"] != OURS}
                or {r["h"] for r in rows if r["case"] == case}, reverse=True)
    print("### %s: joint error at T (rad) over h, and its observed order\n" % case)
    print("| engine / config | " + " | ".join("%g" % h for h in hs) + " | order |")
    print("|---|" + "---:|" * (len(hs) + 1))
    for eng, cfg in configs:
        cells, pts = [], []
        for h in hs:
            r = pick(eng, cfg, case, h)
            if r is None:
                cells.append("")
                continue
            cells.append(fmt(r["q"], r["blew"]))
            if not r["blew"] and 1e-12 < r["q"] < 0.1:
                pts.append((h, r["q"]))
        if not any(cells):
            continue
        s = slope(pts)
        print("| %s | %s | %s |" % (name(eng, cfg), " | ".join(cells), "–" if s is None else "%.2f" % s))
    print()

targets = [1e-3, 1e-6, 1e-9]
for case in cases:
    print("### %s: cheapest run reaching a joint error: %s time per simulated second (ms), and its h\n"
          % (case, "thread-CPU" if args.clock == "cpu" else "wall"))
    print("| engine / config | " + " | ".join("err ≤ %g" % t for t in targets) + " |")
    print("|---|" + "---:|" * len(targets))
    for eng, cfg in configs:
        mine = [r for r in rows if (r["engine"], r["config"], r["case"]) == (eng, cfg, case)
                and not r["blew"] and math.isfinite(cost(r))]
        if not mine:
            continue
        cells = []
        for t in targets:
            ok = [r for r in mine if r["q"] <= t]
            if not ok:
                cells.append("–")
                continue
            # Cost of one simulated second: ns per step x steps per second.
            best = min(ok, key=lambda r: cost(r) / r["h"])
            cells.append("%.3g (h=%g)" % (cost(best) / best["h"] * 1e-6, best["h"]))
        print("| %s | %s |" % (name(eng, cfg), " | ".join(cells)))
    print()

# Table 4: the target "lower error than every peer at equal cost". For every peer point (case,
# engine/config, h) and metric, our lowest error among our runs (any config, any h) that cost no
# more per simulated second; the point is beaten when that error is lower. Errors below
# report.PLOT_FLOOR count as the floor (two results at round-off are not told apart); a peer
# point cheaper than every run of ours, or a blown-up one of ours, cannot beat it.
METRICS = [("q", "joint error"), ("E", "energy drift")]


def floored(v):
    return max(v, report.PLOT_FLOOR)


print("### Target: our error lower than every peer's at equal cost\n")
print("For every peer point (case, config, h: its error and its %s time per simulated second), our "
      "lowest error among our runs that cost no more; the point is beaten when that error is lower "
      "(errors below %g count as %g)." % ("thread-CPU" if args.clock == "cpu" else "wall",
                                            report.PLOT_FLOOR, report.PLOT_FLOOR))
print()
print("| case / metric | target | peer points beaten | not beaten (ratio of errors, ours / peer's: the worst few) |")
print("|---|---|---:|---|")
for case in cases:
    ours = [r for r in rows if r["case"] == case and r["engine"] == OURS and not r["blew"]
            and math.isfinite(cost(r))]
    peers = [r for r in rows if r["case"] == case and r["engine"] != OURS and not r["blew"]
             and math.isfinite(cost(r))]
    if not ours or not peers:
        continue
    for metric, label in METRICS:
        points = [r for r in peers if math.isfinite(r[metric])]
        lost = []
        for p in points:
            budget = cost(p) / p["h"]
            fits = [r for r in ours if cost(r) / r["h"] <= budget and math.isfinite(r[metric])]
            best = min(fits, key=lambda r: floored(r[metric])) if fits else None
            if best is None or not floored(best[metric]) < floored(p[metric]):
                lost.append((p, best))

        def badness(item):
            p, best = item
            return float("inf") if best is None else floored(best[metric]) / floored(p[metric])

        lost.sort(key=badness, reverse=True)
        notes = []
        for p, best in lost[:4]:
            where = "%s %s h=%g: %s at %.3g ms/s" % (p["engine"], p["config"], p["h"], fmt(p[metric]),
                                                     cost(p) / p["h"] * 1e-6)
            if best is None:
                notes.append(where + "; no run of ours as cheap")
            else:
                notes.append(where + "; ours %s (%s h=%g, %.3g ms/s), ×%.3g" % (
                    fmt(best[metric]), best["config"], best["h"], cost(best) / best["h"] * 1e-6,
                    badness((p, best))))
        if len(lost) > 4:
            notes.append("…")
        print("| %s %s | %s | %d of %d | %s |" % (case, label, "met" if not lost else "missed",
                                                  len(points) - len(lost), len(points), "<br>".join(notes)))
print()

if args.plot:
    if not report.gnuplot_available():
        sys.exit("summarize_articulated.py: gnuplot not found: no diagram")
    styles = report.series_styles(configs)
    clock = "thread-CPU" if args.clock == "cpu" else "wall"
    ncol = len(cases) + 1
    script = report.plot_header(args.plot, "", "", "", 640 * len(cases) + 420, 1000)
    script += ('set multiplot layout 2,%d title "Articulated cases: error against cost (one point per h) '
               '(errors < 1e-16 plotted at 1e-16; blown-up runs not plotted)" noenhanced\n' % ncol)
    script += "unset key\n"
    panels = []
    for metric, label in (("q", "joint-position error at T (rad)"), ("E", "energy drift max|E-E0|/E0")):
        for case in cases:
            panels.append((metric, label, case))
        panels.append(None)  # the legend's (or an empty) cell ends each row
    for i, p in enumerate(panels):
        if p is None:
            if i == len(cases):  # end of the first row: the legend
                script += ("unset title\nunset border\nunset tics\nunset xlabel\nunset ylabel\nunset grid\n"
                           "unset logscale\nset xrange [0:1]\nset yrange [0:1]\n"
                           'set key center center noenhanced font ",11" spacing 1.2\n')
                script += "plot " + ", \\\n     ".join('NaN with linespoints %s title "%s"' % (
                    styles[k], report.label(*k)) for k in configs) + "\n"
                script += ('unset key\nset border\nset tics\nset grid xtics ytics lc rgb "#e0e0e0"\n'
                           "set logscale xy\n")
            else:
                script += "set multiplot next\n"
            continue
        metric, label, case = p
        pts_all = [r for r in rows if r["case"] == case and not r["blew"] and math.isfinite(r[metric])
                   and math.isfinite(cost(r))]
        if not pts_all:
            script += "set multiplot next\n"
            continue
        xs = [cost(r) / r["h"] * 1e-6 for r in pts_all]
        ymax = max([max(r[metric], report.PLOT_FLOOR) for r in pts_all] + [1e-15])
        script += 'set title "%s (T = %g s): %s" noenhanced\n' % (case, T_OF.get(case, float("nan")), label)
        script += ('set xlabel "ms of %s time per simulated second (ns per step / h)"\n'
                   'set ylabel "%s" noenhanced\n' % (clock, label))
        script += "set xrange [%g:%g]\n" % (min(xs) / 1.6, max(xs) * 1.6)
        script += "set yrange [%g:%g]\n" % (report.PLOT_FLOOR / 3, 10 ** math.ceil(math.log10(ymax) + 0.3))
        plots = []
        for j, key in enumerate(configs):
            pts = sorted([r for r in pts_all if (r["engine"], r["config"]) == key], key=lambda r: r["h"])
            if not pts:
                continue
            script += "$d%d_%d << EOD\n" % (i, j)
            for r in pts:
                script += "%.6g %.6g\n" % (cost(r) / r["h"] * 1e-6, max(r[metric], report.PLOT_FLOOR))
            script += "EOD\n"
            plots.append("$d%d_%d using 1:2 with linespoints %s notitle" % (i, j, styles[key]))
        script += "plot " + ", \\\n     ".join(plots) + "\n"
    script += "unset multiplot\n"
    if report.run_gnuplot(script, args.plot):
        print("wrote %s" % args.plot, file=sys.stderr)
