#!/usr/bin/env python3
"""robot_state_publisher fed with our /joint_states puts every link where the node's tf does.

Scene: urdf/arm7.urdf (a ceiling-mounted 7-DoF arm; world -> base_link fixed) released at the
bent pose of config/arm7.yaml under gravity; paused and driven by ~step.

Truth: a second implementation of the forward kinematics. The node publishes world -> link
for every link directly, from the bodies the articulated dynamics moved (motors composed down
the tree). Debian's robot_state_publisher, given the same robot_description and our
/joint_states, chains parent -> child transforms with KDL (world -> base_link on its
/tf_static, each joint on its /tf, here remapped to /tf_static_rsp and /tf_rsp); tf2 composes
its chain. Both evaluate the same kinematics in double from the same joint positions: each
link pose is a chain of at most 8 rotations and translations of order 1 m, each rounded to a
few ulps, so they agree to ~1e-15; 1e-9 m and 1e-9 rad leave room for any sane evaluation
order, while a real disagreement (a joint sign, an axis, a stale stamp, a frame offset) is
1e-4 or more at the instants compared.

Also: the node's tf holds every link of the URDF (the tree's links on /tf, the static base on
/tf_static).
"""
import math
import os
import sys
import unittest
import xml.etree.ElementTree as ElementTree

import rosgraph
import rospkg
import rospy
import rostest
import tf2_ros
from sensor_msgs.msg import JointState
from tf2_msgs.msg import TFMessage

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Simulator, max_abs_diff, quat, quat_conj, quat_mul,  # noqa: E402
                           vec, wait_until)

TOL_M = 1e-9
TOL_RAD = 1e-9
RSP = '/robot_state_publisher'
STEPS = [1, 249, 250, 500]  # the instants compared: 1, 250, 500 and 1000 steps after reset


def rotation_angle(p, q):
    """The angle of the rotation taking p to q (unit quaternions, up to the double cover),
    by atan2 (accurate near 0, where acos loses half the digits)."""
    d = quat_mul(quat_conj(p), q)
    return 2.0 * math.atan2(math.sqrt(d[1] ** 2 + d[2] ** 2 + d[3] ** 2), abs(d[0]))


class RobotStatePublisherTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('robot_state_publisher_test')
        urdf = os.path.join(rospkg.RosPack().get_path('cga_rigid_sim'), 'urdf', 'arm7.urdf')
        cls.links = [link.get('name') for link in ElementTree.parse(urdf).getroot()
                     .findall('link') if link.get('name') != 'world']
        cls.node_tf = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.node_tf)
        cls.rsp_tf = tf2_ros.Buffer(debug=False)  # one ~tf2_frames service per node
        subscribers = [
            rospy.Subscriber('/tf_rsp', TFMessage, cls.on_rsp_tf, queue_size=None),
            rospy.Subscriber('/tf_static_rsp', TFMessage, cls.on_rsp_tf_static,
                             queue_size=None)]
        cls.joint_names = []
        subscribers.append(
            rospy.Subscriber('/joint_states', JointState, cls.on_joint_states, queue_size=10))
        cls.sim = Simulator()
        for sub in subscribers:
            wait_until(lambda: sub.get_num_connections() > 0, what=sub.name + ' connected')
        # robot_state_publisher listens to the node's /joint_states.
        master = rosgraph.Master('/robot_state_publisher_test')
        wait_until(lambda: any(t == '/joint_states' and RSP in nodes
                               for t, nodes in master.getSystemState()[1]),
                   what='robot_state_publisher subscribed to /joint_states')
        rospy.sleep(0.5)  # registered with the master; let it connect to the node

    @classmethod
    def on_rsp_tf(cls, msg):
        for t in msg.transforms:
            cls.rsp_tf.set_transform(t, 'robot_state_publisher')

    @classmethod
    def on_rsp_tf_static(cls, msg):
        for t in msg.transforms:
            cls.rsp_tf.set_transform_static(t, 'robot_state_publisher')

    @classmethod
    def on_joint_states(cls, msg):
        cls.joint_names = list(msg.name)

    def lookup(self, buffer, link, stamp):
        t = buffer.lookup_transform('world', link, stamp, rospy.Duration(10.0))
        return vec(t.transform.translation), quat(t.transform.rotation)

    def test_every_link_agrees_with_robot_state_publisher(self):
        self.sim.reset()
        worst_m, worst_rad = 0.0, 0.0
        for steps in STEPS:
            stamp = self.sim.step(steps)
            for link in self.links:
                ours = self.lookup(self.node_tf, link, stamp)
                theirs = self.lookup(self.rsp_tf, link, stamp)
                what = '%s at %.3f s' % (link, stamp.to_sec())
                dx = max_abs_diff(ours[0], theirs[0])
                da = rotation_angle(ours[1], theirs[1])
                self.assertLess(dx, TOL_M, what)
                self.assertLess(da, TOL_RAD, what)
                worst_m, worst_rad = max(worst_m, dx), max(worst_rad, da)
        rospy.loginfo('arm7: node tf vs robot_state_publisher: worst %.3g m, %.3g rad',
                      worst_m, worst_rad)
        self.assertEqual(self.joint_names, ['joint%d' % k for k in range(1, 8)])

    def test_the_arm_moved_between_the_instants(self):
        # Guards the comparison above against a frozen arm (equal tf from stale poses).
        self.sim.reset()
        before = self.lookup(self.node_tf, 'link7', self.sim.step(1))
        after = self.lookup(self.node_tf, 'link7', self.sim.step(250))
        self.assertGreater(max_abs_diff(before[0], after[0]), 1e-3)

    def test_the_node_tf_has_every_link(self):
        self.assertEqual(len(self.links), 8)  # base_link, link1 .. link7
        stamp = self.sim.step(1)
        for link in self.links:
            self.lookup(self.node_tf, link, stamp)  # raises if missing


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'robot_state_publisher_tf', RobotStatePublisherTest)
