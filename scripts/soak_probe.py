#!/usr/bin/env python3
"""Watcher for scripts/soak.sh: samples the simulator's resident memory (VmRSS of its process,
found through the node's own XML-RPC getPid) every second and calls its ~get_body_state every
--every seconds, recording the latency, until SIGINT/SIGTERM; then writes a JSON summary to
--out (samples included)."""
import argparse
import json
import signal
import sys
import time
import xmlrpc.client

import rosgraph
import rospy
from cga_rigid_sim.srv import GetBodyState


def node_pid(node):
    master = rosgraph.Master('/soak_probe')
    api = master.lookupNode(node)
    code, _, pid = xmlrpc.client.ServerProxy(api).getPid('/soak_probe')
    if code != 1:
        raise RuntimeError('getPid failed for ' + node)
    return pid


def rss_kib(pid):
    with open('/proc/%d/status' % pid) as f:
        for line in f:
            if line.startswith('VmRSS:'):
                return int(line.split()[1])
    raise RuntimeError('no VmRSS for pid %d' % pid)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--node', default='/simulator')
    ap.add_argument('--body', default='box_0')
    ap.add_argument('--every', type=float, default=2.0, help='s between service calls')
    ap.add_argument('--timeout', type=float, default=5.0, help='s a service call may take')
    ap.add_argument('--out', required=True)
    args = ap.parse_args(rospy.myargv()[1:])

    rospy.init_node('soak_probe', disable_signals=True)
    service = args.node + '/get_body_state'
    rospy.wait_for_service(service, timeout=30.0)
    get = rospy.ServiceProxy(service, GetBodyState, persistent=False)
    pid = node_pid(args.node)

    stop = []
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))

    start = time.time()
    rss, calls = [], []
    next_rss, next_call = start, start
    while not stop:
        now = time.time()
        if now >= next_rss:
            try:
                rss.append([round(now - start, 3), rss_kib(pid)])
            except (OSError, RuntimeError):
                break  # the node is gone
            next_rss += 1.0
        if now >= next_call:
            t0 = time.time()
            ok, message = False, ''
            try:
                res = get(args.body) if args.timeout <= 0 else _call_with_timeout(
                    get, args.body, args.timeout)
                ok, message = res.success, res.message
            except Exception as e:  # noqa: BLE001 — a failed call is what we record
                message = str(e)
            calls.append([round(t0 - start, 3), round(time.time() - t0, 6), ok, message])
            next_call += args.every
        time.sleep(max(0.0, min(next_rss, next_call) - time.time()))
    with open(args.out, 'w') as f:
        json.dump({'pid': pid, 'rss_kib': rss, 'calls': calls}, f)
    return 0


def _call_with_timeout(proxy, body, timeout):
    # rospy service calls have no timeout of their own: a socket timeout bounds the wait.
    import socket
    old = socket.getdefaulttimeout()
    socket.setdefaulttimeout(timeout)
    try:
        return proxy(body)
    finally:
        socket.setdefaulttimeout(old)


if __name__ == '__main__':
    sys.exit(main())
