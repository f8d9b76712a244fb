#!/usr/bin/env python3
"""Bad inputs are refused, counted, and change nothing; the node keeps running.

Truth: the bodies rest without gravity, so any input that slipped through would move them.
Each bad input (NaN/Inf anywhere, unknown body or frame, a static body, over the limits, a
start stamp already past; bad poses and URDFs on the services) must raise ~rejected_inputs by
exactly one; services answer success=false with a reason. Afterwards, stepping on leaves every
state bit-identical to the start and the total momentum exactly zero.
"""
import os
import sys
import unittest

import rospy
import rostest
from cga_rigid_sim.msg import BodyState
from geometry_msgs.msg import Pose, Twist

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Simulator, body, make_impulse, make_plain_wrench,  # noqa: E402
                           make_wrench, state_fields, vec)

NAN, INF = float('nan'), float('inf')
NS_PER_STEP = 1000000
GOOD_URDF = """<robot name="cube"><link name="cube_link"><inertial><mass value="1"/>
<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link></robot>"""


def unit_pose():
    pose = Pose()
    pose.orientation.w = 1.0
    return pose


class BadInputsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('bad_inputs_test')
        cls.sim = Simulator()

    def refused_topic(self, pub, msg):
        before = self.sim.rejected
        pub.publish(msg)
        self.sim.wait_rejected(before + 1)

    def refused_service(self, call, *args):
        before = self.sim.rejected
        res = call(*args)
        self.assertFalse(res.success)
        self.assertNotEqual(res.message, '')
        self.sim.wait_rejected(before + 1)
        return res.message

    def test_bad_inputs_are_counted_and_change_nothing(self):
        sim = self.sim
        t_start = sim.step(100)  # time 0.1 s: a stamp of 0.05 s is past
        initial = {b: state_fields(sim.get(b)) for b in ['box', 'ball']}
        com = vec(sim.get('box').com)
        ahead = t_start + rospy.Duration(0, 5 * NS_PER_STEP)
        past = rospy.Time(0, 50 * NS_PER_STEP)
        self.assertEqual(sim.rejected, 0)

        W, I, P = sim.wrench_pub, sim.impulse_pub, sim.plain_wrench_pub
        bad_topics = [
            (W, make_wrench('box', (NAN, 0, 0), point=com, stamp=ahead)),
            (W, make_wrench('box', (1, 0, 0), point=(0, INF, 0), stamp=ahead)),
            (W, make_wrench('box', (1, 0, 0), torque=(0, 0, NAN), stamp=ahead)),
            (W, make_wrench('box', (1, 0, 0), alpha=INF, stamp=ahead)),
            (W, make_wrench('box', (1, 0, 0), duration=NAN, stamp=ahead)),
            (W, make_wrench('no_such_body', (1, 0, 0), stamp=ahead)),
            (W, make_wrench('box', (1, 0, 0), frame='no_such_link', stamp=ahead)),
            (W, make_wrench('box', (1, 0, 0), frame='ball', stamp=ahead)),   # another body
            (W, make_wrench('table', (1, 0, 0), stamp=ahead)),               # static body
            (W, make_wrench('box', (2e6, 0, 0), point=com, stamp=ahead)),    # > max_force 1e6
            (W, make_wrench('box', (0, 0, 0), torque=(0, 3e6, 0), stamp=ahead)),
            (W, make_wrench('box', (1, 0, 0), point=com, stamp=past)),       # already past
            (I, make_impulse('box', (0, NAN, 0), stamp=ahead)),
            (I, make_impulse('box', (1, 0, 0), point=(NAN, 0, 0), stamp=ahead)),
            (I, make_impulse('box', (2e4, 0, 0), stamp=ahead)),              # > max_impulse 1e4
            (I, make_impulse('box', (0, 0, 0), torque=(0, 0, 5e4), stamp=ahead)),
            (I, make_impulse('no_such_body', (1, 0, 0), stamp=ahead)),
            (I, make_impulse('box', (1, 0, 0), stamp=past)),
            (P, make_plain_wrench('', (1, 0, 0), stamp=ahead)),             # no link
            (P, make_plain_wrench('world', (1, 0, 0), stamp=ahead)),        # not a link
            (P, make_plain_wrench('no_such_link', (1, 0, 0), stamp=ahead)),
            (P, make_plain_wrench('box_marker', (INF, 0, 0), stamp=ahead)),
            (P, make_plain_wrench('box_marker', (0, 0, 0), (0, NAN, 0), stamp=ahead)),
            (P, make_plain_wrench('box_marker', (0, 2e6, 0), stamp=ahead)),
            (P, make_plain_wrench('table_leg', (1, 0, 0), stamp=ahead)),    # static body
        ]
        for pub, msg in bad_topics:
            self.refused_topic(pub, msg)

        # Services: success=false, a reason, counted.
        zero_quaternion = BodyState(name='box')  # orientation (0, 0, 0, 0)
        message = self.refused_service(sim.set_state, zero_quaternion)
        self.assertIn('orientation', message)
        nan_twist = BodyState(name='box', pose=unit_pose())
        nan_twist.twist.angular.y = NAN
        self.refused_service(sim.set_state, nan_twist)
        self.refused_service(sim.set_state, BodyState(name='no_such_body', pose=unit_pose()))
        self.refused_service(sim.set_state, BodyState(name='table', pose=unit_pose()))
        self.refused_service(sim.spawn, 'junk', '<robot name="junk"><link', unit_pose(), Twist())
        self.refused_service(sim.spawn, 'junk', 'not xml at all', unit_pose(), Twist())
        self.refused_service(sim.spawn, 'box', GOOD_URDF, unit_pose(), Twist())  # name taken
        self.refused_service(sim.spawn, '', GOOD_URDF, unit_pose(), Twist())     # empty name
        nan_pose = unit_pose()
        nan_pose.position.z = NAN
        self.refused_service(sim.spawn, 'cube', GOOD_URDF, nan_pose, Twist())
        self.refused_service(sim.delete, 'no_such_body')
        # A chain of 200 000 links (9 MB) once overflowed urdfdom's recursive tree building and
        # killed the node: the loader's depth bound refuses it before urdfdom sees the text.
        chain = ['<robot name="chain"><link name="l0"/>']
        for k in range(1, 200000):
            chain.append('<joint name="j%d" type="fixed"><parent link="l%d"/><child link="l%d"/>'
                         '</joint><link name="l%d"/>' % (k, k - 1, k, k))
        chain.append('</robot>')
        message = self.refused_service(sim.spawn, 'chain', ''.join(chain), unit_pose(), Twist())
        self.assertIn('kMaxUrdfDepth', message)
        expected = len(bad_topics) + 11
        self.assertEqual(sim.rejected, expected)

        # A failed query is answered but is not an input: not counted.
        res = sim.get_response('no_such_body')
        self.assertFalse(res.success)
        self.assertNotEqual(res.message, '')

        # Nothing was applied: stepping past every stamp leaves the bodies exactly at rest.
        t_end = sim.step(200)
        for name, state in initial.items():
            self.assertEqual(state_fields(sim.get(name)), state, name)
        total = body(sim.momentum_at(t_end), 'total')
        self.assertEqual(vec(total.linear), (0.0, 0.0, 0.0))
        self.assertEqual(vec(total.angular_origin), (0.0, 0.0, 0.0))
        self.assertEqual(sim.rejected, expected)

        # The node still takes good inputs.
        res = sim.spawn('cube', GOOD_URDF, unit_pose(), Twist())
        self.assertTrue(res.success, res.message)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'bad_inputs', BadInputsTest)
