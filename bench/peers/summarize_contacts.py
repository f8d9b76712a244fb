#!/usr/bin/python3
"""Markdown tables (and one diagram) from bench/out/contacts_<engine>.csv: the contact
benchmark, cga_rigid_sim (bench_contacts) beside the peer engines.

    bench/peers/summarize_contacts.py [--out DIR] [--h 0.001] [--clock cpu|wall] [--plot [PNG]]

Table 1: every error metric per engine/config at one step size (default 1 ms).
Table 2: ns per step (wall | thread CPU) per case at that step size.
Table 3: each metric over all step sizes found (h columns), compact.
Table 4 (when our rows are there): per analytic case and metric, every peer point (h, cost,
error) against our lowest error among our runs that cost no more (the target: lower than every
peer's at equal cost); cost = thread-CPU ns per step (--clock wall: wall time).
pile1000: real-time factor (h / time per step) per engine.
--plot: error against ns per step, one log-log panel per analytic case (its first metric),
gnuplot PNG (default doc/img/contacts_work_precision.png), in the style of bench/report.py.
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
                help="cost of table 4 and of the diagram (default: thread CPU time)")
ap.add_argument("--plot", nargs="?", const=os.path.join(root, "doc", "img", "contacts_work_precision.png"),
                help="draw the diagram (gnuplot) to this PNG")
args = ap.parse_args()

OURS = report.OURS
rows, cpu = [], {}
for path in sorted(glob.glob(os.path.join(args.out, "contacts_*.csv"))):
    with open(path) as f:
        rows += list(csv.DictReader(f))
for path in sorted(glob.glob(os.path.join(args.out, "cpu_contacts_*.csv"))):
    with open(path) as f:
        for r in csv.DictReader(f):
            cpu[(r["engine"], r["config"], r["case"], float(r["h"]))] = float(r["cpu_ns_per_step"])

case_order = ["bounce", "incline_stick", "incline_slide", "slide_stop", "rolling_sphere", "stack10", "pile1000"]
analytic = case_order[:-1]
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
configs.sort(key=lambda k: k[0] != OURS)  # ours first, the peers in file order


def fmt(v):
    v = float(v)
    if math.isinf(v):
        return "inf"
    if v == int(v) and abs(v) < 1e4:
        return "%d" % v
    return "%.2e" % v


def name(eng, cfg):
    return ("**%s %s**" if eng == OURS else "%s %s") % (eng, cfg)


def val(eng, cfg, case, metric, h):
    for r in rows:
        if (r["engine"], r["config"], r["case"]) == (eng, cfg, case) and abs(float(r["h"]) - h) < 1e-12:
            if r["error_metric"] == metric:
                return fmt(r["error"])
            if r["error_metric"] == "crashed":
                return "crashed"
    return "-"


def cost(r):
    """ns per step of a row on the chosen clock (NaN when unknown)."""
    if args.clock == "wall":
        return float(r["ns_per_step"])
    return cpu.get((r["engine"], r["config"], r["case"], float(r["h"])), float("nan"))


print("Errors at h = %g s\n" % args.h)
print("| engine / config | " + " | ".join("%s %s" % m for m in metrics) + " |")
print("|---|" + "---:|" * len(metrics))
for eng, cfg in configs:
    print("| %s | " % name(eng, cfg) + " | ".join(val(eng, cfg, c, m, args.h) for c, m in metrics) + " |")

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
    print("| %s | " % name(eng, cfg) + " | ".join(cells) + " |")

hs = sorted({float(r["h"]) for r in rows})
if len(hs) > 1:
    print("\nAll step sizes (h = %s s)\n" % ", ".join("%g" % h for h in hs))
    print("| case / metric | engine / config | " + " | ".join("h=%g" % h for h in hs) + " |")
    print("|---|---|" + "---:|" * len(hs))
    for c, m in metrics:
        if c == "pile1000":
            continue
        for eng, cfg in configs:
            print("| %s %s | %s | " % (c, m, name(eng, cfg)) + " | ".join(val(eng, cfg, c, m, h) for h in hs) + " |")

# ---- table 4: ours against every peer point at equal or lower cost ----------------------------
points = [r for r in rows if r["case"] in analytic and r["error_metric"] != "crashed"
          and math.isfinite(cost(r))]
ours_pts = [r for r in points if r["engine"] == OURS]
if ours_pts:
    floor = report.PLOT_FLOOR
    print("\nOurs against every peer point (%s time per step; errors below %g count as %g)\n"
          % ("thread-CPU" if args.clock == "cpu" else "wall", floor, floor))
    print("| case / metric | target | peer points beaten | not beaten (the worst few) |")
    print("|---|---|---:|---|")
    for c, m in metrics:
        if c not in analytic:
            continue
        peer = [p for p in points if p["engine"] != OURS and (p["case"], p["error_metric"]) == (c, m)]
        mine = [o for o in ours_pts if (o["case"], o["error_metric"]) == (c, m)]
        beaten, lost = 0, []
        for p in peer:
            pe = max(float(p["error"]), floor)
            cand = [o for o in mine if cost(o) <= cost(p)]
            best = min(cand, key=lambda o: (float(o["error"]), cost(o))) if cand else None
            if best is not None and max(float(best["error"]), floor) < pe:
                beaten += 1
            elif best is None:
                lost.append((float("inf"), "%s h=%g: %.0f ns, cheaper than every run of ours" % (
                    report.label(p["engine"], p["config"]), float(p["h"]), cost(p))))
            else:
                be = max(float(best["error"]), floor)
                lost.append((be / pe, "%s h=%g: %s at %.0f ns; ours %s (h=%g)" % (
                    report.label(p["engine"], p["config"]), float(p["h"]), fmt(p["error"]), cost(p),
                    fmt(best["error"]), float(best["h"]))))
        lost.sort(key=lambda t: -t[0])
        print("| %s %s | %s | %d of %d | %s |" % (
            c, m, "met" if not lost else "missed", beaten, len(peer),
            "<br>".join(t for _, t in lost[:4]) + ("<br>…" if len(lost) > 4 else "")))

# ---- pile1000: real-time factor ----------------------------------------------------------------
pile = [r for r in rows if r["case"] == "pile1000" and r["error_metric"] == "max_speed_mps"]
if pile:
    print("\npile1000 real-time factor (h / time per step; wall, thread CPU)\n")
    print("| engine / config | h | simulated | RTF wall | RTF CPU |")
    print("|---|---:|---|---:|---:|")
    for eng, cfg in configs:
        for r in pile:
            if (r["engine"], r["config"]) != (eng, cfg):
                continue
            h = float(r["h"])
            w, cp = float(r["ns_per_step"]), cpu.get((eng, cfg, "pile1000", h), float("nan"))
            print("| %s | %g | %s | %.3g | %.3g |" % (
                name(eng, cfg), h, r["notes"].split("(RTF")[0].replace("at T = ", "").strip(),
                h * 1e9 / w, h * 1e9 / cp))

# ---- the diagram --------------------------------------------------------------------------------
if args.plot:
    if not report.gnuplot_available():
        sys.exit("summarize_contacts.py: gnuplot not found: no diagram")
    panels = []
    for c in analytic:
        ms = [m for cc, m in metrics if cc == c]
        if ms:
            panels.append((c, ms[0]))
    keys = [k for k in configs if any(r["case"] in analytic for r in rows if (r["engine"], r["config"]) == k)]
    styles = report.series_styles(keys)
    clock = "thread-CPU" if args.clock == "cpu" else "wall"
    script = report.plot_header(args.plot, "", "ns per step (%s)" % clock, "error", 1800, 980)
    script += ('set multiplot layout 2,4 title "Contact cases: error against cost, h = %s ms '
               '(errors < 1e-16 plotted at 1e-16; inf not plotted)" noenhanced\n'
               % ", ".join("%g" % (h * 1e3) for h in hs))
    script += "unset key\n"
    for i, (c, m) in enumerate(panels):
        pts_all = [r for r in points if (r["case"], r["error_metric"]) == (c, m) and math.isfinite(float(r["error"]))]
        ymax = max([max(float(r["error"]), report.PLOT_FLOOR) for r in pts_all] + [1e-15])
        xs = [cost(r) for r in pts_all]
        script += 'set title "%s: %s" noenhanced\n' % (c, m)
        lo, hi = min(xs) / 1.6, max(xs) * 1.6  # points off the borders
        script += "set xrange [%g:%g]\n" % (lo, hi)
        if math.log10(hi / lo) < 1.5:  # a narrow panel: tics at 1, 2, 5 x 10^k, plain numbers
            tics = [m * 10.0 ** k for k in range(int(math.floor(math.log10(lo))), int(math.ceil(math.log10(hi))) + 1)
                    for m in (1, 2, 5) if lo <= m * 10.0 ** k <= hi]
            script += "set xtics (%s)\n" % ", ".join('"%d" %g' % (t, t) for t in tics)
        else:
            script += "set xtics autofreq\n"
        script += "set yrange [%g:%g]\n" % (report.PLOT_FLOOR / 3, 10 ** math.ceil(math.log10(ymax) + 0.3))
        plots = []
        for j, key in enumerate(keys):
            pts = sorted([r for r in pts_all if (r["engine"], r["config"]) == key], key=lambda r: float(r["h"]))
            if not pts:
                continue
            script += "$d%d_%d << EOD\n" % (i, j)
            for r in pts:
                script += "%.6g %.6g\n" % (cost(r), max(float(r["error"]), report.PLOT_FLOOR))
            script += "EOD\n"
            plots.append("$d%d_%d using 1:2 with linespoints %s notitle" % (i, j, styles[key]))
        script += "plot " + ", \\\n     ".join(plots) + "\n"
    # The legend in a panel of its own.
    script += ("unset title\nunset border\nunset tics\nunset xlabel\nunset ylabel\nunset grid\n"
               "unset logscale\nset xrange [0:1]\nset yrange [0:1]\n"
               'set key center center noenhanced font ",12" spacing 1.3\n')
    script += "plot " + ", \\\n     ".join('NaN with linespoints %s title "%s"' % (
        styles[k], report.label(*k)) for k in keys) + "\n"
    script += "unset multiplot\n"
    if report.run_gnuplot(script, args.plot):
        print("\nwrote %s" % args.plot, file=sys.stderr)
