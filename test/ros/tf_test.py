#!/usr/bin/env python3
"""tf2 shows every link where the URDF puts it.

Truth: the URDF (test/ros/bodies.urdf). The bodies rest (no gravity, no velocity), so the
running node's tf of every link must equal the pose its joints give, to round-off (the motor
round trip URDF pose -> M_WB -> pose costs a few ulps). Merged links come from /tf_static
(root link -> link), moving roots from /tf, the static body from /tf_static; a spawned body and
its merged link appear, and the latched /tf_static holds every static frame in one message.
"""
import os
import sys
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Pose, Twist
from tf2_msgs.msg import TFMessage

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Simulator, compose, max_abs_diff, quat, quat_distance,  # noqa: E402
                           rpy_to_quat, vec, wait_until)

TOL = 1e-12  # m and quaternion units: a few ulps of the pose round trip

# (parent, child, xyz, rpy) of the URDF's joints.
URDF_JOINTS = {
    'box': ('world', (0.5, -0.2, 1.0), (0.3, -0.2, 0.1)),
    'box_marker': ('box', (0.1, 0.0, 0.15), (0.0, 0.0, 1.5707963267948966)),
    'ball': ('world', (-1.0, 0.5, 0.3), (0.0, 0.0, 0.0)),
    'table': ('world', (0.0, 0.0, 0.4), (0.0, 0.0, 0.5)),
    'table_leg': ('table', (0.3, 0.2, -0.2), (0.0, 0.0, 0.0)),
}

PROBE_URDF = """<?xml version="1.0"?>
<robot name="probe">
  <link name="probe_root">
    <inertial><mass value="1.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.025"/></inertial>
  </link>
  <joint name="probe_to_tip" type="fixed">
    <parent link="probe_root"/><child link="probe_tip"/>
    <origin xyz="0.0 0.0 0.25" rpy="0.0 0.5 0.0"/>
  </joint>
  <link name="probe_tip">
    <inertial><mass value="0.1"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
</robot>
"""


def urdf_pose_in_world(link):
    """World pose (t, q) of a link by composing the URDF joint origins."""
    parent, xyz, rpy = URDF_JOINTS[link]
    pose = (xyz, rpy_to_quat(*rpy))
    if parent == 'world':
        return pose
    return compose(urdf_pose_in_world(parent), pose)


class TfTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('tf_test')
        cls.buffer = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.buffer)
        cls.sim = Simulator()

    def lookup(self, child, timeout=10.0):
        t = self.buffer.lookup_transform('world', child, rospy.Time(0), rospy.Duration(timeout))
        return vec(t.transform.translation), quat(t.transform.rotation)

    def assertPose(self, actual, expected, what):
        self.assertLess(max_abs_diff(actual[0], expected[0]), TOL, what + ' translation')
        self.assertLess(quat_distance(actual[1], expected[1]), TOL, what + ' rotation')

    def test_every_link_at_its_urdf_pose(self):
        for link in URDF_JOINTS:
            self.assertPose(self.lookup(link), urdf_pose_in_world(link), link)

    def test_body_state_pose_is_the_root_link(self):
        state = self.sim.get('box')
        pose = (vec(state.pose.position), quat(state.pose.orientation))
        self.assertPose(pose, urdf_pose_in_world('box'), 'get_body_state(box).pose')

    def test_tf_is_stamped_with_simulation_time_and_never_repeats(self):
        stamps = []
        sub = rospy.Subscriber('/tf', TFMessage,
                               lambda m: stamps.extend(t.header.stamp for t in m.transforms
                                                       if t.child_frame_id == 'box'))
        wait_until(lambda: len(stamps) >= 20, what='20 tf messages')
        sub.unregister()
        got = list(stamps)
        self.assertEqual(len(got), len(set(got)), 'a tf stamp repeated')
        # 100 Hz of simulation time on the 1 ms step grid: consecutive stamps 10 ms apart.
        for a, b in zip(got, got[1:]):
            self.assertEqual((b - a).to_nsec(), 10000000)

    def test_spawned_body_and_latched_static_frames(self):
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = 2.0, -1.0, 0.5
        pose.orientation.w = 1.0
        res = self.sim.spawn('probe', PROBE_URDF, pose, Twist())
        self.assertTrue(res.success, res.message)
        self.assertPose(self.lookup('probe'), ((2.0, -1.0, 0.5), (1.0, 0.0, 0.0, 0.0)), 'probe')
        tip = compose(((2.0, -1.0, 0.5), (1.0, 0.0, 0.0, 0.0)),
                      ((0.0, 0.0, 0.25), rpy_to_quat(0.0, 0.5, 0.0)))
        self.assertPose(self.lookup('probe_tip'), tip, 'probe_tip')

        # A late subscriber gets one latched message with every static frame.
        latched = rospy.wait_for_message('/tf_static', TFMessage, timeout=10.0)
        children = sorted(t.child_frame_id for t in latched.transforms)
        self.assertEqual(children, ['box_marker', 'probe_tip', 'table', 'table_leg'])

        res = self.sim.delete('probe')
        self.assertTrue(res.success, res.message)
        wait_until(lambda: sorted(
            t.child_frame_id for t in
            rospy.wait_for_message('/tf_static', TFMessage, timeout=10.0).transforms) ==
            ['box_marker', 'table', 'table_leg'], what='/tf_static without probe_tip')


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'tf', TfTest)
