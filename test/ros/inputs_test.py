#!/usr/bin/env python3
"""Wrenches and impulses change momentum by exactly what they carry.

Truths (Newton–Euler, free bodies, no gravity, paused node driven by ~step so every number
belongs to a known step):
  - a CgaWrench f through the centre of mass for a duration d changes the linear momentum by
    f d and leaves the angular momentum zero (tolerance 1e-12 relative: a few hundred
    additions of f dt, each rounded);
  - a CgaImpulse J at r from the centre of mass changes the linear momentum by J and the
    angular momentum about the centre of mass by r x J (tolerance 1e-9, as specified);
  - the plain geometry_msgs/WrenchStamped path and the CgaWrench path with the same link frame,
    force and torque give bit-identical states (second method, same core input);
  - alpha (F = f + alpha n) never changes the motion: alpha = 0 and 1e3 give identical states;
  - a wrench of negative duration acts until ~clear_wrenches.
Each case starts from ~reset (all bodies at rest at their URDF poses).
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Simulator, add, body, cross, make_impulse, make_plain_wrench,  # noqa
                           make_wrench, max_abs_diff, norm, scale, state_fields, sub, vec)

DT = 0.001  # s, the node's ~dt (set in the .test)
NS_PER_STEP = 1000000


class InputsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('inputs_test')
        cls.sim = Simulator()

    def fresh_start(self):
        """Reset, then one step so the outputs at the current stamp show the reset state."""
        self.sim.reset()
        t = self.sim.step(1)
        return t, self.sim.momentum_at(t)

    def ahead(self, t, steps):
        return t + rospy.Duration(0, steps * NS_PER_STEP)

    def test_wrench_through_com_changes_linear_momentum_by_f_times_d(self):
        t0, m0 = self.fresh_start()
        com = vec(self.sim.get('box').com)
        f = (3.0, -1.5, 2.25)  # N
        d = 0.25               # s = 250 steps
        start = self.ahead(t0, 10)
        self.sim.wrench_pub.publish(make_wrench('box', f, point=com, stamp=start, duration=d))
        self.sim.barrier(self.sim.wrench_pub)

        t_before = self.sim.step(10)  # up to the start: nothing yet
        self.assertEqual(t_before, start)
        p_before = vec(body(self.sim.momentum_at(t_before), 'box').linear)
        self.assertEqual(p_before, vec(body(m0, 'box').linear))

        t_end = self.sim.step(250)
        m_end = body(self.sim.momentum_at(t_end), 'box')
        expected = scale(d, f)
        self.assertLess(max_abs_diff(sub(vec(m_end.linear), p_before), expected),
                        1e-12 * norm(expected))
        self.assertLess(norm(vec(m_end.angular)), 1e-12 * norm(expected))

        # The wrench is over: momentum stays.
        t_after = self.sim.step(100)
        self.assertEqual(vec(body(self.sim.momentum_at(t_after), 'box').linear),
                         vec(m_end.linear))

    def test_impulse_off_com_changes_angular_momentum_by_r_cross_j(self):
        t0, _ = self.fresh_start()
        com = vec(self.sim.get('box').com)
        J = (0.3, -0.2, 0.5)      # N s
        r = (0.02, 0.05, -0.04)   # m from the centre of mass
        start = self.ahead(t0, 5)
        self.sim.impulse_pub.publish(make_impulse('box', J, point=add(com, r), stamp=start))
        self.sim.barrier(self.sim.impulse_pub)
        t = self.sim.step(20)
        m = body(self.sim.momentum_at(t), 'box')
        self.assertLess(max_abs_diff(vec(m.linear), J), 1e-9)
        self.assertLess(max_abs_diff(vec(m.angular), cross(r, J)), 1e-9)
        total = body(self.sim.momentum_at(t), 'total')
        self.assertLess(max_abs_diff(vec(total.linear), J), 1e-9)

    def test_plain_wrench_equals_cga_wrench(self):
        force, torque = (1.0, -2.0, 0.5), (0.05, 0.02, -0.1)

        t0, _ = self.fresh_start()
        at_rest = state_fields(self.sim.get('box'))
        self.sim.wrench_pub.publish(make_wrench('box', force, torque=torque, frame='box_marker',
                                                stamp=self.ahead(t0, 3)))
        self.sim.barrier(self.sim.wrench_pub)
        self.sim.step(50)
        cga_path = state_fields(self.sim.get('box'))

        t0, _ = self.fresh_start()
        self.sim.plain_wrench_pub.publish(make_plain_wrench('box_marker', force, torque,
                                                            stamp=self.ahead(t0, 3)))
        self.sim.barrier(self.sim.plain_wrench_pub)
        self.sim.step(50)
        plain_path = state_fields(self.sim.get('box'))

        self.assertNotEqual(cga_path, at_rest)
        self.assertEqual(cga_path, plain_path)

    def test_alpha_never_changes_the_motion(self):
        states = []
        for alpha in [0.0, 1e3]:
            t0, _ = self.fresh_start()
            self.sim.wrench_pub.publish(make_wrench('box', (0.5, 1.0, -0.2), point=(0.6, -0.1, 1.1),
                                                    stamp=self.ahead(t0, 2), duration=0.05,
                                                    alpha=alpha))
            self.sim.impulse_pub.publish(make_impulse('box', (0.1, 0.0, 0.2),
                                                      point=(0.5, -0.25, 1.0),
                                                      stamp=self.ahead(t0, 4), alpha=alpha))
            self.sim.barrier(self.sim.wrench_pub)
            self.sim.barrier(self.sim.impulse_pub)
            self.sim.step(100)
            states.append(state_fields(self.sim.get('box')))
        self.assertEqual(states[0], states[1])

    def test_negative_duration_acts_until_cleared(self):
        t0, _ = self.fresh_start()
        com = vec(self.sim.get('ball').com)
        f = (0.0, 0.0, 1.0)
        self.sim.wrench_pub.publish(make_wrench('ball', f, point=com, stamp=self.ahead(t0, 1),
                                                duration=-1.0))
        self.sim.barrier(self.sim.wrench_pub)
        t = self.sim.step(501)  # steps t0+1 … t0+500 carry the wrench
        p = vec(body(self.sim.momentum_at(t), 'ball').linear)
        self.assertLess(max_abs_diff(p, scale(500 * DT, f)), 1e-12)
        self.sim.clear_wrenches()
        t = self.sim.step(100)
        self.assertEqual(vec(body(self.sim.momentum_at(t), 'ball').linear), p)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'inputs', InputsTest)
