#!/usr/bin/env python3
"""~pause, ~unpause, ~step and ~reset do what they say, and /clock carries simulation time.

Truths:
  - ~step N while paused advances the simulation time by exactly N dt (integer nanoseconds),
    and tf sees each stamp once (tf2 warns TF_REPEATED_DATA otherwise);
  - paused, simulation time stands still (however long the wall clock runs);
  - unpaused at real_time_factor 1, simulation time follows wall time (±15 % over 1.5 s, for
    a loaded CI machine) and ~pause stops it;
  - ~reset puts every body back to its initial state bit for bit while time runs on;
  - a node with use_sim_time (this test) reads the simulator's time from /clock.
The bodies fall under gravity, so a state that did not move back on reset would show.
"""
import os
import sys
import time
import unittest

import rospy
import rostest
from tf2_msgs.msg import TFMessage

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import Simulator, state_fields, wait_until  # noqa: E402

NS_PER_STEP = 1000000  # dt = 1 ms


class TimeControlTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('time_control_test')
        assert rospy.get_param('/use_sim_time'), 'the .test sets /use_sim_time'
        cls.sim = Simulator()
        # The node starts paused: nothing has moved yet.
        cls.initial = {b: state_fields(cls.sim.get(b)) for b in ['box', 'ball']}

    def setUp(self):
        self.sim.pause()

    def test_step_while_paused_advances_exactly_n_dt(self):
        t0 = self.sim.time()
        for n in [1, 7, 1234]:
            t1 = self.sim.step(n)
            self.assertEqual((t1 - t0).to_nsec(), n * NS_PER_STEP)
            t0 = t1

    def test_step_publishes_tf_once_per_stamp(self):
        # Steps that end on a tick (the tick is published during the steps) and steps that do
        # not (the final state is published once more): every stamp reaches tf exactly once.
        stamps = []
        sub = rospy.Subscriber('/tf', TFMessage, lambda m: stamps.extend(
            t.header.stamp for t in m.transforms if t.child_frame_id == 'box'))
        wait_until(lambda: sub.get_num_connections() > 0, what='/tf connected')
        to_tick = -(self.sim.time().to_nsec() // NS_PER_STEP) % 10
        if to_tick:
            self.sim.step(to_tick)  # so the steps below start on a tick (every 10 steps)
        ends = [self.sim.step(n) for n in [10, 0, 5, 5, 1, 9, 0, 20]]
        wait_until(lambda: ends[-1] in stamps, what='the last tf')
        sub.unregister()
        self.assertEqual(len(stamps), len(set(stamps)), 'a tf stamp repeated')
        for t in ends:
            self.assertIn(t, stamps)

    def test_paused_time_stands_still(self):
        t0, s0 = self.sim.time(), state_fields(self.sim.get('box'))
        time.sleep(0.5)
        self.assertEqual(self.sim.time(), t0)
        self.assertEqual(state_fields(self.sim.get('box')), s0)

    def test_unpaused_runs_at_real_time_and_pause_stops(self):
        t0, w0 = self.sim.time(), time.time()
        self.sim.unpause()
        time.sleep(1.5)
        self.sim.pause()
        t1, w1 = self.sim.time(), time.time()
        ratio = (t1 - t0).to_sec() / (w1 - w0)
        rospy.loginfo('real_time_factor 1: achieved %.3f', ratio)
        self.assertGreater(ratio, 0.85)
        self.assertLess(ratio, 1.15)
        time.sleep(0.3)
        self.assertEqual(self.sim.time(), t1)

    def test_reset_restores_the_initial_state_and_time_runs_on(self):
        self.sim.step(500)
        moved = state_fields(self.sim.get('box'))
        self.assertNotEqual(moved, self.initial['box'])
        t_before = self.sim.time()
        self.sim.reset()
        self.assertEqual(self.sim.time(), t_before)
        for name, initial in self.initial.items():
            self.assertEqual(state_fields(self.sim.get(name)), initial, name)
        t_after = self.sim.step(3)
        self.assertEqual((t_after - t_before).to_nsec(), 3 * NS_PER_STEP)

    def test_clock_carries_simulation_time(self):
        t = self.sim.step(25)
        wait_until(lambda: rospy.get_rostime() == t, what='rospy time == %s' % t)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'time_control', TimeControlTest)
