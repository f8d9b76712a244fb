#!/usr/bin/env python3
"""Input flood for scripts/soak.sh: valid, invalid and over-the-bounds messages mixed, at a
target rate, for a time; then prints a JSON line with what it sent and how many of those
messages the simulator must refuse.

Every message is one of (by a fixed cycle of 100, so the mix is the same at any rate):
  valid      70 %  one-step wrenches and next-step impulses on box_2 … box_<n-1> (tiny forces;
                   they pass through the queue within a step or two), and WrenchStamped on a link
  invalid    10 %  NaN force, unknown body, force above ~max_force, unknown frame: refused always
  far        15 %  impulses on box_0 stamped 1e6 s ahead (valid, never due): the first
                   ~max_queued_inputs_per_body wait, every later one is refused on arrival
  forever     5 %  until-cleared wrenches (negative duration) on box_1: the first
                   ~max_active_wrenches_per_body act, every later one is refused at its start
So the refusals the node must count are exactly
  invalid + max(0, far − max_queued_inputs_per_body) + max(0, forever − max_active_wrenches_per_body),
provided the queue in all stays below ~max_queued_inputs (it holds the far ones plus a few
steps of valid ones) and the active wrenches below ~max_active_wrenches.

Publishers are synchronous (queue_size=None): rospy never drops a message on the sending side.
"""
import argparse
import json
import math
import sys
import time

import rospy
from cga_rigid_sim.msg import CgaImpulse, CgaWrench
from geometry_msgs.msg import WrenchStamped


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--node', default='/simulator')
    ap.add_argument('--rate', type=float, default=10000.0, help='messages per second')
    ap.add_argument('--seconds', type=float, default=300.0)
    ap.add_argument('--bodies', type=int, default=100, help='box_0 … box_<n-1>')
    ap.add_argument('--max-queued-per-body', type=int, default=1000)
    ap.add_argument('--max-active-per-body', type=int, default=64)
    args = ap.parse_args(rospy.myargv()[1:])

    rospy.init_node('soak_flood', disable_signals=True)
    wrench_pub = rospy.Publisher(args.node + '/apply_wrench', CgaWrench, queue_size=None)
    impulse_pub = rospy.Publisher(args.node + '/apply_impulse', CgaImpulse, queue_size=None)
    plain_pub = rospy.Publisher(args.node + '/wrench', WrenchStamped, queue_size=None)
    deadline = time.time() + 20.0
    while time.time() < deadline and min(p.get_num_connections() for p in
                                         (wrench_pub, impulse_pub, plain_pub)) == 0:
        time.sleep(0.05)
    if min(p.get_num_connections() for p in (wrench_pub, impulse_pub, plain_pub)) == 0:
        print('soak_flood: the simulator does not subscribe to its input topics', file=sys.stderr)
        return 2
    time.sleep(0.5)  # connections settle

    far_stamp = rospy.Time(1000000)
    counts = {'valid': 0, 'invalid': 0, 'far': 0, 'forever': 0}

    def wrench(body, fx, duration=0.0, frame=''):
        m = CgaWrench(body=body, duration=duration)
        m.header.frame_id = frame
        m.f.x = fx
        return m

    def impulse(body, jx, stamp=None):
        m = CgaImpulse(body=body)
        if stamp is not None:
            m.header.stamp = stamp
        m.f.x = jx
        return m

    start = time.time()
    n = 0
    while True:
        now = time.time()
        elapsed = now - start
        if elapsed >= args.seconds:
            break
        due = int(elapsed * args.rate)
        if n >= due:
            time.sleep(min(0.001, (n + 1) / args.rate - elapsed))
            continue
        for _ in range(min(due - n, 1000)):  # catch up, a bounded burst at a time
            k = n % 100
            body = 'box_%d' % (2 + n % (args.bodies - 2))
            if k < 35:
                wrench_pub.publish(wrench(body, 1e-3))
                counts['valid'] += 1
            elif k < 60:
                impulse_pub.publish(impulse(body, 1e-6))
                counts['valid'] += 1
            elif k < 70:
                m = WrenchStamped()
                m.header.frame_id = body
                m.wrench.force.y = 1e-3
                plain_pub.publish(m)
                counts['valid'] += 1
            elif k < 73:
                wrench_pub.publish(wrench(body, math.nan))
                counts['invalid'] += 1
            elif k < 76:
                impulse_pub.publish(impulse('no_such_body', 1.0))
                counts['invalid'] += 1
            elif k < 78:
                wrench_pub.publish(wrench(body, 2e6))  # > ~max_force
                counts['invalid'] += 1
            elif k < 80:
                wrench_pub.publish(wrench(body, 1.0, frame='no_such_frame'))
                counts['invalid'] += 1
            elif k < 95:
                impulse_pub.publish(impulse('box_0', 1e-6, stamp=far_stamp))
                counts['far'] += 1
            else:
                wrench_pub.publish(wrench('box_1', 1e-6, duration=-1.0))
                counts['forever'] += 1
            n += 1
    wall = time.time() - start
    refusable = (counts['invalid'] + max(0, counts['far'] - args.max_queued_per_body) +
                 max(0, counts['forever'] - args.max_active_per_body))
    print(json.dumps({'sent': n, 'seconds': wall, 'rate': n / wall, 'counts': counts,
                      'refusable': refusable}), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
