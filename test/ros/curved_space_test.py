#!/usr/bin/env python3
"""Curved space through the node: ~curvature, tf in the stereographic chart, ~curved_momentum.

Truths (doc/curved_space.md): without inputs the 4-d world momentum and the energy on
~curved_momentum are constant (the ball is isotropic, so `auto` takes the exact flow: round-off);
the ball's true speed |v| is constant (its translation part only turns), and the chart is
conformal with ds = |dx| / (1 + |x|^2/(4 R^2)), so the speed read from consecutive tf positions,
times that factor, is |v| (to the O(dt^2) of the finite difference), while the raw chart speed
is not. An impulse through the ball's centre adds its 4-d moment to the world momentum. And a
curved node with gravity on refuses to start, naming the rule.
"""
import math
import os
import sys
import threading
import unittest

import rospy
import rostest
from tf2_msgs.msg import TFMessage

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Simulator, make_impulse, norm, start_failure, sub,  # noqa: E402
                           wait_until)
from cga_rigid_sim.msg import CurvedMomentumArray  # noqa: E402

R = 5.0
V0 = [0.5, -0.2, 0.3]   # m/s, the launch file's initial linear velocity
STEPS = 2000            # 2 s at dt = 1 ms; ticks every 10 steps (100 Hz)
CHUNK = 500


class CurvedSpaceTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('curved_space_test')
        cls.lock = threading.Lock()
        cls.curved = {}   # stamp -> CurvedMomentumArray
        cls.tf = {}       # stamp -> translation of world -> ball
        subs = [rospy.Subscriber('/simulator/curved_momentum', CurvedMomentumArray,
                                 cls._on_curved, queue_size=None),
                rospy.Subscriber('/tf', TFMessage, cls._on_tf, queue_size=None)]
        cls.sim = Simulator()
        for s in subs:
            wait_until(lambda: s.get_num_connections() > 0, what=s.name + ' connected')
        t0 = cls.sim.time()
        for _ in range(STEPS // CHUNK):
            cls.sim.step(CHUNK)
        wait_until(lambda: len(cls.after(cls.curved, t0)) >= STEPS // 10 and
                   len(cls.after(cls.tf, t0)) >= STEPS // 10, what='ticks of 2 s')
        cls.t0 = t0

    @classmethod
    def _on_curved(cls, msg):
        with cls.lock:
            cls.curved[msg.header.stamp] = msg

    @classmethod
    def _on_tf(cls, msg):
        with cls.lock:
            for t in msg.transforms:
                if t.child_frame_id == 'ball':
                    v = t.transform.translation
                    cls.tf[t.header.stamp] = [v.x, v.y, v.z]

    @classmethod
    def after(cls, table, t):
        with cls.lock:
            return sorted(s for s in table if s > t)

    def test_four_d_momentum_and_energy_are_constant(self):
        stamps = self.after(self.curved, self.t0)
        first = self.curved[stamps[0]]
        self.assertEqual(first.curvature_radius, R)
        self.assertEqual([b.body for b in first.bodies], ['ball', 'total'])
        L0 = list(first.bodies[-1].world_momentum)
        T0 = first.bodies[-1].kinetic_energy
        self.assertGreater(norm(L0), 0.1)
        worst_L = worst_T = 0.0
        for s in stamps:
            total = self.curved[s].bodies[-1]
            worst_L = max(worst_L, max(abs(a - b) for a, b in zip(total.world_momentum, L0)))
            worst_T = max(worst_T, abs(total.kinetic_energy - T0))
        rospy.loginfo('curved momentum over %d ticks: |dL_W| %.2e (|L_W| %.3f), |dT| %.2e J',
                      len(stamps), worst_L, norm(L0), worst_T)
        # The exact flow evaluated from its anchor: round-off of one evaluation, a few ulps of
        # |L_W| ~ 3 kg m^2/s and of T ~ 0.2 J.
        self.assertLess(worst_L, 1e-12 * norm(L0))
        self.assertLess(worst_T, 1e-13 * T0)

    def test_tf_is_the_conformal_chart(self):
        stamps = self.after(self.tf, self.t0)
        speed = norm(V0)
        worst_true = 0.0
        raw_last = None
        for a, b in zip(stamps, stamps[1:]):
            xa, xb = self.tf[a], self.tf[b]
            dt = (b - a).to_sec()
            mid = [(p + q) / 2 for p, q in zip(xa, xb)]
            chart_speed = norm(sub(xb, xa)) / dt
            true_speed = chart_speed / (1.0 + sum(c * c for c in mid) / (4 * R * R))
            worst_true = max(worst_true, abs(true_speed - speed) / speed)
            raw_last = abs(chart_speed - speed) / speed
        rospy.loginfo('tf chart: true speed within %.2e of |v|; raw chart speed off by %.2e at '
                      'the end (|x| = %.2f m)', worst_true, raw_last, norm(self.tf[stamps[-1]]))
        # The finite difference over 10 ms: the chord of a path curved on the scale of R and of
        # the spin coupling, and the midpoint rule for the factor: O((v dt)^2 / R^2) ~ 1e-7;
        # 1e-5 leaves room. The raw chart speed is off by ~|x|^2/(4R^2) ~ 1e-2 at the end.
        self.assertLess(worst_true, 1e-5)
        self.assertGreater(raw_last, 1e-3)

    def test_zz_impulse_adds_its_four_d_moment(self):
        # Last (after the tests that read the free motion). An impulse j through the ball's centre
        # in its own frame has the body moment O^J = (0; R j) (doc/curved_space.md (C12)); the
        # world momentum gains it carried by the pose, psi (O^J) psi~, a conjugation by a rotor
        # of Spin(4), which keeps the coefficient norm of an so(4) bivector: |dL_W| = R |j|.
        # Tolerance: round-off of a few ulps of |L_W| ~ 3 and R |j| = 1.
        j = (0.2, 0.0, 0.0)
        t_now = self.sim.time()
        before = [s for s in self.after(self.curved, self.t0) if s <= t_now][-1]
        self.sim.impulse_pub.publish(make_impulse('ball', j, frame='ball',
                                                  stamp=t_now + rospy.Duration(0.05)))
        rospy.sleep(0.5)  # delivered before the steps below
        t_end = self.sim.step(200)
        wait_until(lambda: self.after(self.curved, t_end - rospy.Duration(0.001)),
                   what='a tick after the impulse')
        after = self.after(self.curved, t_now + rospy.Duration(0.1))[-1]
        L0 = self.curved[before].bodies[-1].world_momentum
        L1 = self.curved[after].bodies[-1].world_momentum
        dL = norm([a - b for a, b in zip(L1, L0)])
        rospy.loginfo('impulse through the centre: |dL_W| = %.15f, R |j| = %.15f', dL, R * norm(j))
        self.assertLess(abs(dL - R * norm(j)), 1e-12 * (norm(L0) + R * norm(j)))

    def test_gravity_on_is_refused(self):
        status, out = start_failure('curved_with_gravity', '_curvature:=5.0',
                                    '_urdf_file:=' + os.path.join(os.path.dirname(
                                        os.path.realpath(__file__)), 'ball.urdf'))
        self.assertNotEqual(status, 0, out)
        self.assertIn('curvature: needs gravity off', out)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'curved_space', CurvedSpaceTest)
