#!/usr/bin/env python3
"""A run driven by stamped trajectory commands, recorded with rosbag and replayed into a fresh
paused node, is reproduced bit for bit.

Truth: determinism of the World (same scene, same controllers, same stamped commands in the
same order, same steps -> bit-identical states). The run: the arm7 with
config/arm7_controllers.yaml at real time; the test sends three trajectories on
/run/arm_controller/command stamped ahead of the run's clock - the second replaces the first
while it runs, the third (empty) stops and holds - while rosbag records the topic. A fresh
paused node gets the bag's messages in order and is stepped to the run's steps: its
/joint_states at the run's last joint-state tick and every link's state at the run's last step
must be equal to the run's - not close: equal.
"""
import os
import sys
import tempfile
import threading
import unittest

import rosbag
import rospy
import rostest
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Recorder, Simulator, joint_fields, make_trajectory,  # noqa: E402
                           state_fields, wait_until)

RUN, REPLAY = '/run', '/replay'
JOINTS = ['joint%d' % k for k in range(1, 8)]
LINKS = ['link%d' % k for k in range(1, 8)]
NS_PER_STEP = 1000000


class Arm(object):
    def __init__(self, ns):
        self.sim = Simulator(ns + '/simulator')
        self.joint_states = {}
        self.lock = threading.Lock()
        self.command = rospy.Publisher(ns + '/arm_controller/command', JointTrajectory,
                                       queue_size=10)
        sub = rospy.Subscriber(ns + '/joint_states', JointState, self._on_joints,
                               queue_size=None)
        for topic in [self.command, sub]:
            wait_until(lambda: topic.get_num_connections() > 0, what=topic.name + ' connected')

    def _on_joints(self, msg):
        with self.lock:
            self.joint_states[msg.header.stamp] = msg


def command(stamp, points):
    return make_trajectory(JOINTS, [(t, q, None) for t, q in points], stamp)


class ReplayControllersTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('replay_controllers_test')
        cls.live = Arm(RUN)
        cls.replay = Arm(REPLAY)

    def test_replay_of_trajectory_commands_is_bit_identical(self):
        bag_path = os.path.join(tempfile.mkdtemp(prefix='cga_rigid_sim_'), 'commands.bag')
        recorder = Recorder(bag_path, [RUN + '/arm_controller/command'])
        try:
            now = self.live.sim.time()
            base = (now.to_nsec() // NS_PER_STEP + 300) * NS_PER_STEP

            def at(steps):
                return rospy.Time(0, base + steps * NS_PER_STEP)
            wait_until(lambda: self.live.joint_states, what='/run/joint_states')
            q = list(self.live.joint_states[max(self.live.joint_states)].position)
            far = [a + d for a, d in zip(q, (0.5, -0.4, 0.4, 0.5, -0.5, 0.5, 0.6))]
            mid = [(a + b) / 2 for a, b in zip(q, far)]
            back = [a + d for a, d in zip(q, (-0.2, 0.1, -0.2, 0.2, 0.3, -0.2, -0.3))]
            self.live.command.publish(command(at(0), [(0.5, mid), (1.0, far)]))
            self.live.command.publish(command(at(600), [(0.7, back)]))  # replaces it at 0.6 s
            self.live.command.publish(command(at(1000), []))  # stop and hold
            wait_until(lambda: self.live.sim.time() > at(1400), timeout=30.0, period=0.05,
                       what='the run past its commands')
            self.live.sim.pause()
            t_end = self.live.sim.time()
            links_run = {b: state_fields(self.live.sim.get(b)) for b in LINKS}
            self.assertEqual(self.live.sim.rejected, 0, 'the run refused a command')
        finally:
            recorder.stop()
        with self.live.lock:
            t_tick = max(self.live.joint_states)
            joints_run = joint_fields(self.live.joint_states[t_tick])
            moved = max(abs(a - b) for a, b in
                        zip(self.live.joint_states[t_tick].position, q))
        # The commands moved the arm (held where the stop found it, 0.1 rad and more from
        # where it started): the replay reproduces a driven run, not a resting one.
        self.assertGreater(moved, 0.1)

        count = 0
        with rosbag.Bag(bag_path) as bag:
            for _, msg, _ in bag.read_messages():
                self.replay.command.publish(msg)
                count += 1
        self.assertEqual(count, 3)
        # Refused after them on the same connection: once counted, all three are queued.
        self.replay.command.publish(JointTrajectory())
        self.replay.sim.wait_rejected(1)

        self.assertEqual(self.replay.sim.time(), rospy.Time(0))
        t = self.replay.sim.step(t_tick.to_nsec() // NS_PER_STEP)
        self.assertEqual(t, t_tick)
        wait_until(lambda: t in self.replay.joint_states, what='/replay/joint_states')
        self.assertEqual(joint_fields(self.replay.joint_states[t]), joints_run)
        t = self.replay.sim.step((t_end - t_tick).to_nsec() // NS_PER_STEP)
        self.assertEqual(t, t_end)
        for b in LINKS:
            self.assertEqual(state_fields(self.replay.sim.get(b)), links_run[b], b)
        rospy.loginfo('replay: %d trajectory commands, %d steps, joint states and links '
                      'bit-identical', count, t_end.to_nsec() // NS_PER_STEP)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'replay_controllers', ReplayControllersTest)
