#!/usr/bin/env python3
"""/tf and ~body_states as a second thread fills and sends them (~threads 2, 600 bodies).

Truth: the URDF (scripts/generate_many_bodies.py 600, read back from robot_description). The
boxes rest (no gravity, no velocity), so at every output tick each box's transform in /tf and
its pose in ~body_states must equal its floating joint's origin, to round-off (the motor round
trip URDF pose -> M_WB -> pose costs a few ulps), every box must be in both, and the two
messages of one tick must carry the same stamp and the same poses.
"""
import os
import sys
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
from cga_rigid_sim.msg import BodyStateArray
from tf2_msgs.msg import TFMessage

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import quat, quat_distance, rpy_to_quat, wait_until  # noqa: E402

BODIES = 600
TOL = 1e-12  # m and quaternion units: a few ulps of the pose round trip


def urdf_poses():
    """Per box link: (xyz, quaternion) of its floating joint's origin in the world."""
    robot = ET.fromstring(rospy.get_param('/robot_description'))
    poses = {}
    for joint in robot.findall('joint'):
        origin = joint.find('origin')
        xyz = tuple(float(v) for v in origin.get('xyz', '0 0 0').split())
        rpy = tuple(float(v) for v in origin.get('rpy', '0 0 0').split())
        poses[joint.find('child').get('link')] = (xyz, rpy_to_quat(*rpy))
    return poses


class ThreadedOutputs(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('threaded_outputs_test')
        cls.tf = []
        cls.states = []
        rospy.Subscriber('/tf', TFMessage, lambda m: cls.tf.append(m), queue_size=100)
        rospy.Subscriber('/simulator/body_states', BodyStateArray,
                         lambda m: cls.states.append(m), queue_size=100)
        wait_until(lambda: len(cls.states) >= 5 and len(cls.tf) >= 5, timeout=60.0,
                   what='five ticks of /tf and ~body_states')

    def test_every_box_at_its_urdf_pose_in_both(self):
        truth = urdf_poses()
        self.assertEqual(len(truth), BODIES)
        stamps = {m.header.stamp for m in self.states[1:5]}
        for msg in self.tf[1:5]:
            by_child = {t.child_frame_id: t.transform for t in msg.transforms}
            self.assertEqual(len(by_child), BODIES)
            for link, (xyz, q) in truth.items():
                t = by_child[link]
                self.assertLess(max(abs(t.translation.x - xyz[0]), abs(t.translation.y - xyz[1]),
                                    abs(t.translation.z - xyz[2])), TOL, link)
                self.assertLess(quat_distance(quat(t.rotation), q), TOL, link)
        for msg in self.states[1:5]:
            self.assertEqual(len(msg.bodies), BODIES)
            for body in msg.bodies:
                xyz, q = truth[body.name]
                p = body.pose.position
                self.assertLess(max(abs(p.x - xyz[0]), abs(p.y - xyz[1]), abs(p.z - xyz[2])), TOL,
                                body.name)
                self.assertLess(quat_distance(quat(body.pose.orientation), q), TOL, body.name)
        # A tick's two messages: one read of the simulation, sent by the helper thread.
        tf_stamps = {m.transforms[0].header.stamp for m in self.tf[1:5]}
        self.assertTrue(stamps & tf_stamps, 'no tick whose /tf and ~body_states share a stamp')


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'threaded_outputs', ThreadedOutputs)
