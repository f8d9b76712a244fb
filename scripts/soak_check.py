#!/usr/bin/env python3
"""Checks of scripts/soak.sh: reads the bag, the flood's and the probe's results and the
node's final ~rejected_inputs; prints a summary; exits 1 if a check failed.

Checks:
  ticks    every /tf, ~momentum and ~body_states message of the bag, from the first common
           stamp to the last, is there exactly once, 1/rate apart (no gap, no repeat)
  rejected ~rejected_inputs equals the refusable messages the flood sent
  memory   resident memory after the first --warmup seconds: max − min ≤ --rss-limit MiB
  service  every ~get_body_state call succeeded, each within --latency-limit s
"""
import argparse
import json
import struct
import sys

import rosbag


def stamps(bag, topic, tf):
    """Header stamps in ns, read from the serialised bytes (fast: no full deserialisation). A
    std_msgs/Header starts with seq (uint32), then stamp secs, nsecs (uint32 each); a
    TFMessage starts with its array length (uint32), then its first transform's header."""
    out = []
    offset = 8 if tf else 4
    for _, msg, _ in bag.read_messages(topics=[topic], raw=True):
        data = msg[1]
        secs, nsecs = struct.unpack_from('<II', data, offset)
        out.append(secs * 1000000000 + nsecs)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--bag', required=True)
    ap.add_argument('--node', default='/simulator')
    ap.add_argument('--flood', required=True, help="soak_flood.py's JSON line")
    ap.add_argument('--probe', required=True, help="soak_probe.py's JSON file")
    ap.add_argument('--rejected', type=int, required=True, help='final ~rejected_inputs')
    ap.add_argument('--rate', type=float, default=100.0, help='~publish_rate, Hz')
    ap.add_argument('--warmup', type=float, default=30.0)
    ap.add_argument('--rss-limit', type=float, default=4.0, help='MiB')
    ap.add_argument('--latency-limit', type=float, default=1.0, help='s')
    args = ap.parse_args()

    failures = []
    period = int(round(1e9 / args.rate))
    topics = {'/tf': True, args.node + '/momentum': False, args.node + '/body_states': False}
    with rosbag.Bag(args.bag) as bag:
        series = {t: stamps(bag, t, tf) for t, tf in topics.items()}
    first = max(s[0] for s in series.values() if s) if all(series.values()) else None
    last = min(s[-1] for s in series.values() if s) if all(series.values()) else None
    print('ticks:')
    if first is None:
        failures.append('ticks: a topic is missing from the bag')
    else:
        expected = (last - first) // period + 1
        for t, s in series.items():
            inside = [x for x in s if first <= x <= last]
            gaps = sum(1 for a, b in zip(inside, inside[1:]) if b - a > period)
            off = sum(1 for a, b in zip(inside, inside[1:]) if b - a != period)
            ok = len(inside) == expected and off == 0
            print('  %-28s %7d ticks of %d expected over %.2f s, %d gaps, %d spacings != %d ms%s'
                  % (t, len(inside), expected, (last - first) / 1e9, gaps, off, period // 1000000,
                     '' if ok else '  FAILED'))
            if not ok:
                failures.append('ticks: %s has %d of %d ticks (%d gaps)'
                                % (t, len(inside), expected, gaps))

    with open(args.flood) as f:
        flood = json.loads(f.read().strip().splitlines()[-1])
    print('inputs: %d messages in %.1f s (%.0f per s): %s' % (
        flood['sent'], flood['seconds'], flood['rate'], flood['counts']))
    ok = args.rejected == flood['refusable']
    print('rejected: ~rejected_inputs = %d, refusable sent = %d%s' % (
        args.rejected, flood['refusable'], '' if ok else '  FAILED'))
    if not ok:
        failures.append('rejected: %d counted, %d refusable sent' % (args.rejected,
                                                                     flood['refusable']))

    with open(args.probe) as f:
        probe = json.load(f)
    rss = probe['rss_kib']
    later = [kib for t, kib in rss if t >= args.warmup]
    if len(later) < 2:
        failures.append('memory: fewer than 2 samples after the warm-up')
    else:
        spread = (max(later) - min(later)) / 1024.0
        ok = spread <= args.rss_limit
        print('memory: RSS %.1f MiB at start, %.1f–%.1f MiB after %.0f s (%d samples): '
              'max − min = %.2f MiB (limit %.1f)%s' % (
                  rss[0][1] / 1024.0, min(later) / 1024.0, max(later) / 1024.0, args.warmup,
                  len(later), spread, args.rss_limit, '' if ok else '  FAILED'))
        if not ok:
            failures.append('memory: RSS spread %.2f MiB' % spread)

    calls = probe['calls']
    bad = [c for c in calls if not c[2]]
    lat = sorted(c[1] for c in calls if c[2])
    if not calls or bad:
        failures.append('service: %d of %d calls failed%s' % (
            len(bad), len(calls), (': ' + bad[0][3]) if bad else ''))
    if lat:
        median = lat[len(lat) // 2]
        ok = lat[-1] <= args.latency_limit
        print('service: %d calls of ~get_body_state, %d failed; latency median %.1f ms, '
              'max %.1f ms (limit %.0f ms)%s' % (len(calls), len(bad), median * 1e3,
                                                 lat[-1] * 1e3, args.latency_limit * 1e3,
                                                 '' if ok else '  FAILED'))
        if not ok:
            failures.append('service: latency %.3f s' % lat[-1])

    if failures:
        print('SOAK FAILED: ' + '; '.join(failures))
        return 1
    print('SOAK PASSED')
    return 0


if __name__ == '__main__':
    sys.exit(main())
