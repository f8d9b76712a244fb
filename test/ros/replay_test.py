#!/usr/bin/env python3
"""Replaying a recorded bag of inputs into a fresh paused node reproduces a run bit for bit.

Truth: determinism of the World (same scene, same stamped inputs, same steps → bit-identical
states). The run: a node running in real time under gravity, a spinning box; the test sends
wrenches (world and link frame, plain and CGA) and impulses stamped a little ahead of the run's
clock while rosbag records the input topics. Then a second, fresh node (paused, never stepped)
gets the bag's messages in order and is driven by ~step to the run's final step. Every number of
every body's state must be equal — not close: equal.
"""
import os
import sys
import tempfile
import unittest

import rosbag
import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Recorder, Simulator, add, make_impulse, make_plain_wrench,  # noqa: E402
                           make_wrench, state_fields, vec, wait_until)

RUN, REPLAY = '/run/simulator', '/replay/simulator'
INPUTS = ['apply_wrench', 'apply_impulse', 'wrench']
NS_PER_STEP = 1000000
BODIES = ['box', 'ball']


class ReplayTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('replay_test')
        cls.live = Simulator(RUN)
        cls.replay = Simulator(REPLAY)

    def test_replay_into_a_paused_node_is_bit_identical(self):
        bag_path = os.path.join(tempfile.mkdtemp(prefix='cga_rigid_sim_'), 'inputs.bag')
        recorder = Recorder(bag_path, [RUN + '/' + t for t in INPUTS])
        try:
            # Inputs stamped ahead of the running clock, each in its own step.
            now = self.live.time()
            base = (now.to_nsec() // NS_PER_STEP + 300) * NS_PER_STEP

            def at(steps):
                return rospy.Time(0, base + steps * NS_PER_STEP)
            com = vec(self.live.get('box').com)
            live = self.live
            live.wrench_pub.publish(make_wrench(
                'box', (1.0, 2.0, 3.0), point=add(com, (0.03, 0.0, -0.02)), stamp=at(0),
                duration=0.3, alpha=5.0))
            live.impulse_pub.publish(make_impulse(
                'box', (0.1, -0.2, 0.05), point=add(com, (0.0, 0.04, 0.01)),
                torque=(0.001, 0.0, -0.002), stamp=at(50)))
            live.plain_wrench_pub.publish(make_plain_wrench(
                'box_marker', (0.5, 0.0, 0.0), (0.0, 0.01, 0.0), stamp=at(120)))
            live.wrench_pub.publish(make_wrench(
                'box', (0.0, 0.0, 4.0), point=(0.0, 0.05, 0.0), torque=(0.0, 0.0, 0.02),
                frame='box_marker', stamp=at(200), duration=0.1))
            live.impulse_pub.publish(make_impulse(
                'ball', (0.0, 0.3, 0.3), point=(0.01, 0.0, 0.0), frame='ball', stamp=at(260)))
            wait_until(lambda: self.live.time() > at(600), timeout=30.0, period=0.05,
                       what='the run past its inputs')
            self.live.pause()
            t_end = self.live.time()
            states_run = {b: state_fields(self.live.get(b)) for b in BODIES}
            if rospy.get_param('~contacts', False):  # replay_contacts.test: the run had contacts
                self.assertLess(self.live.get('ball').com.z, 0.1 + 1e-3,
                                'the ball (radius 0.1 m) has landed on the plane')
            self.assertEqual(self.live.rejected, 0, 'the run refused an input')
        finally:
            recorder.stop()

        # Replay the bag, in its order, into the fresh node; make sure it has them all.
        publishers = {'apply_wrench': self.replay.wrench_pub,
                      'apply_impulse': self.replay.impulse_pub,
                      'wrench': self.replay.plain_wrench_pub}
        count = 0
        with rosbag.Bag(bag_path) as bag:
            for topic, msg, _ in bag.read_messages():
                publishers[topic.rsplit('/', 1)[1]].publish(msg)
                count += 1
        self.assertEqual(count, 5)
        for pub in publishers.values():
            self.replay.barrier(pub)
        self.assertEqual(self.replay.rejected, 3, 'only the three barriers are refused')

        self.assertEqual(self.replay.time(), rospy.Time(0))
        t_replay = self.replay.step(t_end.to_nsec() // NS_PER_STEP)
        self.assertEqual(t_replay, t_end)
        for b in BODIES:
            replayed = state_fields(self.replay.get(b))
            self.assertEqual(replayed, states_run[b], b)
        rospy.loginfo('replay: %d inputs, %d steps, states of %s bit-identical', count,
                      t_end.to_nsec() // NS_PER_STEP, BODIES)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'replay', ReplayTest)
