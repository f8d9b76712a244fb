#!/usr/bin/env python3
"""Two copies of the 7-DoF arm spawned under namespaces through ~spawn_urdf, each driven on its
own controller's topics, then one deleted through ~delete_body, as a user does it.

Scene: test/ros/ball.urdf (a free ball: no joints, so no /joint_states and no controller at
start), config/arm7_controllers.yaml in the node's namespace, ~spawn_controllers naming
arm_controller and joint_state_controller; dt = 1 ms, paused and driven by ~step.

Truths:
  - a spawned arm is named under its namespace: its joints on /joint_states and its links on tf
    as r1/joint1, r1/link1, ...; its static base on the latched /tf_static; its trajectory
    controller at /r1/arm_controller/command and /r1/arm_controller/state (a joint state
    controller is not copied: the one /joint_states carries every robot);
  - each arm follows its own trajectory within the YAML's path tolerance (0.05 rad) and ends
    within the goal tolerance (0.01 rad); r2's trajectory names the joints as its URDF does
    (joint1, ...), which its controller takes too;
  - refusals (a namespace that is no ROS name, a namespace whose names are taken, a NaN pose, a
    malformed URDF, a part of a robot deleted alone) each count once on ~rejected_inputs and
    change nothing: the robots step on as before;
  - after ~delete_body r2, its joints leave /joint_states, its frames leave /tf and
    /tf_static, its controller's topics are closed (the node no longer subscribes to
    /r2/arm_controller/command nor publishes /r2/arm_controller/state), and r1 goes on
    tracking a new trajectory within its tolerances.
"""
import math
import os
import sys
import threading
import unittest

import rosgraph
import rospkg
import rospy
import rostest
from cga_rigid_sim.msg import JointTrajectoryControllerState
from geometry_msgs.msg import Pose, Twist
from sensor_msgs.msg import JointState
from tf2_msgs.msg import TFMessage
from trajectory_msgs.msg import JointTrajectory

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import Simulator, make_trajectory, wait_until  # noqa: E402

JOINTS = ['joint%d' % k for k in range(1, 8)]
PATH_TOL = 0.05  # rad, constraints.<joint>.trajectory in arm7_controllers.yaml
GOAL_TOL = 0.01  # rad, constraints.<joint>.goal
GOAL_TIME = 1.0  # s, constraints.goal_time
GOALS = {'r1': (0.4, 0.6, 0.2, -1.0, 0.4, 0.6, 0.3),
         'r2': (-0.3, -0.5, 0.1, 0.8, -0.2, -0.4, 0.2)}


def arm_urdf():
    path = os.path.join(rospkg.RosPack().get_path('cga_rigid_sim'), 'urdf', 'arm7.urdf')
    with open(path) as f:
        return f.read()


def unit_pose():
    p = Pose()
    p.orientation.w = 1.0
    return p


def pose_at(x, y):
    p = unit_pose()
    p.position.x, p.position.y = x, y
    return p


class SpawnRobotsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('spawn_robots_test')
        cls.sim = Simulator('/simulator')
        cls.lock = threading.Lock()
        cls.joint_states, cls.tf, cls.states = {}, {}, {'r1': {}, 'r2': {}}
        cls.subs = [rospy.Subscriber('/joint_states', JointState, cls._on_joints,
                                     queue_size=None),
                    rospy.Subscriber('/tf', TFMessage, cls._on_tf, queue_size=None)]
        for ns in ('r1', 'r2'):
            cls.subs.append(rospy.Subscriber(
                '/%s/arm_controller/state' % ns, JointTrajectoryControllerState,
                lambda m, ns=ns: cls._on_state(ns, m), queue_size=None))
        cls.commands = {ns: rospy.Publisher('/%s/arm_controller/command' % ns, JointTrajectory,
                                            queue_size=10) for ns in ('r1', 'r2')}

    @classmethod
    def _on_joints(cls, msg):
        with cls.lock:
            cls.joint_states[msg.header.stamp] = msg

    @classmethod
    def _on_tf(cls, msg):
        with cls.lock:
            for t in msg.transforms:
                cls.tf.setdefault(t.header.stamp, set()).add(t.child_frame_id)

    @classmethod
    def _on_state(cls, ns, msg):
        with cls.lock:
            cls.states[ns][msg.header.stamp] = msg

    def step(self, n):
        t = self.sim.step(n)
        wait_until(lambda: t in self.joint_states, what='/joint_states at %s' % t)
        wait_until(lambda: t in self.tf, what='/tf at %s' % t)
        return t

    def refused(self, call, *args, **kwargs):
        before = self.sim.rejected
        res = call(*args, **kwargs)
        self.assertFalse(res.success)
        self.sim.wait_rejected(before + 1)
        return res.message

    def track(self, robots, names):
        """Sends each robot its goal, steps through the trajectory and goal time, and checks
        the path and goal tolerances on its controller's state and on /joint_states."""
        t0 = self.sim.time()
        js = self.joint_states[t0]
        for ns in robots:
            q0 = [js.position[list(js.name).index(ns + '/' + j)] for j in JOINTS]
            q2 = GOALS[ns]
            q1 = [(a + b) / 2 for a, b in zip(q0, q2)]
            v1 = [(b - a) / 2.0 for a, b in zip(q0, q2)]
            joint_names = [ns + '/' + j for j in JOINTS] if names == 'prefixed' else JOINTS
            self.commands[ns].publish(make_trajectory(joint_names, [(1.0, q1, v1),
                                                                    (2.0, q2, [0.0] * 7)]))
            # Refused after it on the same connection: once counted, the trajectory is queued
            # for the next step.
            before = self.sim.rejected
            self.commands[ns].publish(JointTrajectory())
            self.sim.wait_rejected(before + 1)
        t_end = self.step(int(round((2.0 + GOAL_TIME) * 1000)))
        final = self.joint_states[t_end]
        for ns in robots:
            wait_until(lambda: t_end in self.states[ns], what='/%s/arm_controller/state' % ns)
            window = [s for s in self.states[ns] if t0 < s <= t_end]
            self.assertGreater(len(window), 100)
            worst = max(max(abs(e) for e in self.states[ns][s].error.positions) for s in window)
            self.assertLessEqual(worst, PATH_TOL, ns)
            q = [final.position[list(final.name).index(ns + '/' + j)] for j in JOINTS]
            goal_error = max(abs(a - b) for a, b in zip(q, GOALS[ns]))
            self.assertLessEqual(goal_error, GOAL_TOL, ns)
            rospy.loginfo('%s: worst path error %.3g rad, goal error %.3g rad', ns, worst,
                          goal_error)

    def test_spawn_drive_delete(self):
        urdf = arm_urdf()
        self.assertEqual(self.sim.rejected, 0)
        for ns, x in (('r1', 3.0), ('r2', -3.0)):
            res = self.sim.spawn(ns, urdf, pose_at(x, 0.0), Twist(), ns)
            self.assertTrue(res.success, res.message)
        # Bad requests: each refused, counted, naming the field and the rule.
        msg = self.refused(self.sim.spawn, 'r3', urdf, pose_at(0, 3), Twist(), 'r 3')
        self.assertIn('spawn_urdf.robot_namespace', msg)
        self.assertIn('not a valid ROS name', msg)
        msg = self.refused(self.sim.spawn, 'r3', urdf, pose_at(0, 3), Twist(), 'r1')
        self.assertIn("link 'r1/base_link' clashes", msg)
        nan_pose = pose_at(0, 3)
        nan_pose.position.z = float('nan')
        msg = self.refused(self.sim.spawn, 'r3', urdf, nan_pose, Twist(), 'r3')
        self.assertIn('not finite', msg)
        self.refused(self.sim.spawn, 'r3', urdf[:200], pose_at(0, 3), Twist(), 'r3')
        msg = self.refused(self.sim.delete, 'r1/link3')
        self.assertIn("belongs to the spawned robot 'r1'", msg)
        self.assertEqual(self.sim.rejected, 5)

        for pub in self.commands.values():
            wait_until(lambda: pub.get_num_connections() > 0, what=pub.name + ' connected')
        for sub in self.subs:
            wait_until(lambda: sub.get_num_connections() > 0, what=sub.name + ' connected')
        t = self.step(1)
        names = list(self.joint_states[t].name)
        self.assertEqual(names, ['r1/' + j for j in JOINTS] + ['r2/' + j for j in JOINTS])
        for ns in ('r1', 'r2'):
            self.assertTrue({ns + '/link1', ns + '/link7'} <= self.tf[t], self.tf[t])
        static = rospy.wait_for_message('/tf_static', TFMessage, timeout=10.0)
        statics = {tr.child_frame_id for tr in static.transforms}
        self.assertTrue({'r1/base_link', 'r2/base_link'} <= statics, statics)

        # r1 named by its prefixed joints, r2 by its URDF's.
        self.track(['r1'], 'prefixed')
        self.track(['r2'], 'urdf')

        res = self.sim.delete('r2')
        self.assertTrue(res.success, res.message)
        t = self.step(1)
        self.assertEqual(list(self.joint_states[t].name), ['r1/' + j for j in JOINTS])
        self.assertFalse({f for f in self.tf[t] if f.startswith('r2/')}, self.tf[t])
        self.assertIn('r1/link7', self.tf[t])
        wait_until(lambda: not any(
            tr.child_frame_id.startswith('r2/') for tr in
            rospy.wait_for_message('/tf_static', TFMessage, timeout=10.0).transforms),
            what='/tf_static without r2')
        master = rosgraph.Master('/spawn_robots_test')

        def served(topic, kind):
            publishers, subscribers, _ = master.getSystemState()
            entries = subscribers if kind == 'sub' else publishers
            return any(name == topic and '/simulator' in nodes for name, nodes in entries)
        wait_until(lambda: not served('/r2/arm_controller/command', 'sub'),
                   what='the node to unsubscribe /r2/arm_controller/command')
        wait_until(lambda: not served('/r2/arm_controller/state', 'pub'),
                   what='the node to stop publishing /r2/arm_controller/state')
        self.assertTrue(served('/r1/arm_controller/command', 'sub'))
        self.assertEqual(self.sim.rejected, 7)  # and the barriers of track()

        GOALS['r1'] = (-0.2, 0.3, -0.3, -0.6, 0.5, 0.2, -0.4)
        self.track(['r1'], 'prefixed')
        self.assertTrue(all(math.isfinite(v) for v in self.joint_states[self.sim.time()].position))


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'spawn_robots', SpawnRobotsTest)
