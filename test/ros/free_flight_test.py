#!/usr/bin/env python3
"""Free flight for 10 s conserves the scene's total momentum.

Truth: no gravity, no inputs: the total linear momentum P and the total angular momentum about
the world origin L_O are constants of the motion, and so is the angular momentum about the
system's centre of mass. The box tumbles about all three axes (asymmetric, off its principal
axes) and both bodies translate, so every quantity is non-trivial. Every ~momentum message of
the 10 s (1000 ticks at 100 Hz) must match the first to 1e-10 relative (the integrators conserve
P and L to round-off; 1e-10 leaves room for 10^4 steps of it).
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import Simulator, body, max_abs_diff, norm, vec, wait_until  # noqa: E402

STEPS = 10000       # 10 s at dt = 1 ms
CHUNK = 500         # steps per ~step call: 50 momentum messages each
TICKS = STEPS // 10  # ticks after the start: every 10 steps
REL_TOL = 1e-10


class FreeFlightTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('free_flight_test')
        cls.sim = Simulator()

    def test_total_momentum_constant_for_10_s(self):
        t0 = self.sim.time()
        for _ in range(STEPS // CHUNK):
            t_last = self.sim.step(CHUNK)
        self.assertEqual((t_last - t0).to_nsec(), STEPS * 1000000)

        wait_until(lambda: len(self.sim.momentum_stamps_after(t0)) >= TICKS,
                   what='%d momentum ticks' % TICKS)
        stamps = self.sim.momentum_stamps_after(t0)

        first = body(self.sim.momenta[stamps[0]], 'total')
        P0, L0, Lc0 = vec(first.linear), vec(first.angular_origin), vec(first.angular)
        self.assertGreater(norm(P0), 0.1)
        self.assertGreater(norm(Lc0), 0.01)
        worst = [0.0, 0.0, 0.0]
        for stamp in stamps:
            total = body(self.sim.momenta[stamp], 'total')
            worst[0] = max(worst[0], max_abs_diff(vec(total.linear), P0) / norm(P0))
            worst[1] = max(worst[1], max_abs_diff(vec(total.angular_origin), L0) / norm(L0))
            worst[2] = max(worst[2], max_abs_diff(vec(total.angular), Lc0) / norm(Lc0))
        rospy.loginfo('free flight %d ticks: worst relative drift P %.2e, L_origin %.2e, '
                      'L_com %.2e', len(stamps), *worst)
        self.assertLess(worst[0], REL_TOL, 'linear momentum')
        self.assertLess(worst[1], REL_TOL, 'angular momentum about the origin')
        self.assertLess(worst[2], REL_TOL, 'angular momentum about the centre of mass')


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'free_flight', FreeFlightTest)
