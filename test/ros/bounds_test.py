#!/usr/bin/env python3
"""Bounds on inputs through the node, and parameters typed as text.

Truths:
- The node of bounds.test got every parameter as a string: gravity "[0, 0, 0]", dt "1e-3",
  paused "true", initial_state "{box: {...}}", the bounds "500", "400", "20", "8". They took
  effect: time stands still until ~step, which advances exactly N·1e-3 s; the box starts with
  the velocities given; without gravity the total momentum stays what it was (1e-12 relative,
  round-off of the momentum sums).
- A flood of N = 800 valid far-future impulses against max_queued_inputs = 500 raises
  ~rejected_inputs by exactly N − 500; 450 on one body against max_queued_inputs_per_body = 400
  by exactly 50; 12 until-cleared wrenches on one body against max_active_wrenches_per_body = 8
  by exactly 4, when they are due; the warnings name the bounds.
- A node started rosrun-style (_gravity:=[0,0,0] _dt:=1 _paused:=true _initial_state:={...})
  reads them as meant: a ball at 1 m/s moves exactly 3 m in 3 steps of 1 s; a value that cannot
  be read exits 1 saying how to write it.
"""
import os
import sys
import threading
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Simulator, body, make_impulse, make_wrench,  # noqa: E402
                           start_failure, start_simulator, vec, wait_until, BARRIER)
from cga_rigid_sim.msg import CgaImpulse, CgaWrench  # noqa: E402

URDF = os.path.join(os.path.dirname(os.path.realpath(__file__)), 'bodies.urdf')
FAR = rospy.Time(1000000)  # 1e6 s: never due in this test


class BoundsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('bounds_test')
        cls.warnings = []
        cls.started = 0
        cls.lock = threading.Lock()
        rospy.Subscriber('/rosout', Log, cls.on_log, queue_size=1000)
        cls.sim = Simulator()
        # Publishers that never drop: the flood is sent in bursts below roscpp's 1000-message
        # subscriber queue, and these queues hold a whole burst.
        cls.impulses = rospy.Publisher('/simulator/apply_impulse', CgaImpulse, queue_size=2000)
        cls.wrenches = rospy.Publisher('/simulator/apply_wrench', CgaWrench, queue_size=2000)
        for pub in [cls.impulses, cls.wrenches]:
            wait_until(lambda: pub.get_num_connections() > 0, what=pub.name + ' connected')

    @classmethod
    def on_log(cls, msg):
        if msg.level == Log.WARN:
            with cls.lock:
                cls.warnings.append(msg.msg)

    def warned(self, text):
        wait_until(lambda: any(text in m for m in self.warnings), what='a warning with ' + text)

    def settle(self, pub, expected):
        """Waits until the node has taken every message sent on `pub` — an input it must refuse
        (unknown body), sent on the same connection after them, is counted — and checks that
        the refusals are `expected` before it. Returns the count after it."""
        pub.publish((CgaImpulse if pub is self.impulses else CgaWrench)(body=BARRIER))
        wait_until(lambda: self.sim.rejected is not None and self.sim.rejected >= expected + 1,
                   what='~rejected_inputs >= %d' % (expected + 1))
        rospy.sleep(0.2)  # a refusal too many would arrive meanwhile
        self.assertEqual(self.sim.rejected, expected + 1)
        return expected + 1

    def test_1_string_parameters_took_effect(self):
        sim = self.sim
        t0 = sim.time()
        rospy.sleep(0.3)
        self.assertEqual(sim.time(), t0)  # paused: "true"
        box = sim.get('box')
        # initial_state as a string (world axes; 1e-12: round-off of the body-frame round trip)
        for got, want in [(box.twist.angular, (0.5, -1.0, 2.0)), (box.twist.linear, (0.25, 0, 0))]:
            for x, y in zip(vec(got), want):
                self.assertAlmostEqual(x, y, delta=1e-12)
        t1 = sim.step(250)
        self.assertEqual((t1 - t0).to_nsec(), 250 * 1000000)  # dt: "1e-3"
        p1 = body(sim.momentum_at(t1), 'total')
        t2 = sim.step(500)
        p2 = body(sim.momentum_at(t2), 'total')
        for a, b in [(p1.linear, p2.linear), (p1.angular_origin, p2.angular_origin)]:
            scale = max(1.0, max(abs(x) for x in vec(a)))
            for x, y in zip(vec(a), vec(b)):
                self.assertLess(abs(x - y), 1e-12 * scale)  # gravity: "[0, 0, 0]"
        self.assertGreater(abs(p2.linear.x), 0.2)  # the box moves: the check is not vacuous

    def test_2_a_flood_past_the_bounds_is_counted_exactly(self):
        sim = self.sim
        sim.reset()
        count = self.settle(self.impulses, self.sim.rejected)
        rospy.sleep(1.2)  # warnings are throttled to one a second per topic: the barrier's passes
        # Total: 800 valid far-future impulses, alternating bodies (400 each, within the
        # per-body bound): the first 500 wait, the other 300 are refused.
        for i in range(800):
            self.impulses.publish(make_impulse('box' if i % 2 else 'ball', (0.1, 0, 0),
                                               stamp=FAR))
        count = self.settle(self.impulses, count + 800 - 500)
        self.warned('max_queued_inputs = 500')
        # Per body: after a reset (which drops what waits), 450 on the box: 50 refused.
        sim.reset()
        rospy.sleep(1.2)
        for i in range(450):
            self.impulses.publish(make_impulse('box', (0.1, 0, 0), stamp=FAR))
        count = self.settle(self.impulses, count + 450 - 400)
        self.warned("body 'box' already has 400 inputs waiting for their step "
                    "(max_queued_inputs_per_body = 400)")
        # Active: 12 until-cleared wrenches on the box, due at the next step: 8 start, 4 are
        # refused when that step runs.
        sim.reset()
        for i in range(12):
            self.wrenches.publish(make_wrench('box', (0.01, 0, 0), duration=-1.0))
        count = self.settle(self.wrenches, count)
        sim.step(1)
        wait_until(lambda: sim.rejected == count + 4, what='4 refused at their start')
        self.warned("body 'box' already has 8 active wrenches at step")
        self.warned('(max_active_wrenches_per_body = 8)')
        sim.clear_wrenches()
        sim.reset()

    def test_3_rosrun_style_parameters_are_read_as_meant(self):
        proc = start_simulator('rosrun_sim', '_urdf_file:=' + URDF, '_gravity:=[0,0,0]',
                               '_dt:=1', '_paused:=true', '_publish_clock:=false',
                               '_initial_state:={ball: {linear_velocity: [0.0, 0.0, 1.0]}}')
        try:
            other = Simulator('/rosrun_sim')
            z0 = other.get('ball').pose.position.z
            t = other.step(3)
            self.assertEqual(t.to_nsec(), 3 * 1000000000)  # dt: 1 (an int)
            self.assertAlmostEqual(other.get("ball").pose.position.z - z0, 3.0, delta=1e-12)  # 1 m/s
        finally:
            proc.terminate()
            proc.communicate(timeout=10.0)
        for args, expected in [
                (['_gravity:=[0,0]'], '~gravity: expected a list of 3 numbers such as '
                 '[0.0, 0.0, -9.81], got string \'[0,0]\' (rosrun: _gravity:="[0.0, 0.0, -9.81]")'),
                (['_paused:=maybe'], '~paused: expected true or false, got string \'maybe\''),
                (['_dt:=fast'], '~dt: expected a number, got string \'fast\' (rosrun: _dt:=0.001)'),
                (['_initial_state:=[1, 2]'], '~initial_state: expected a dictionary such as'),
                (['_max_queued_inputs:=0'], '~max_queued_inputs: must be a whole number from 1')]:
            BoundsTest.started += 1  # a fresh name: parameters stay on the server after a node
            status, out = start_failure('bad_sim_%d' % BoundsTest.started, '_urdf_file:=' + URDF,
                                        *args)
            self.assertEqual(status, 1, out)
            self.assertIn(expected, out)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'bounds', BoundsTest)
