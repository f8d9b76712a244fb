#!/usr/bin/env python3
"""The running node offers exactly the topics and services of test/interface.yaml, with their
types, and the node's reference, doc/node.md (linked from README.md), documents every entry of it.

Truth: the manifest (the public contract). The master's system state lists what the node
registered; roscpp's own ~get_loggers, ~set_logger_level and /rosout are not part of the
contract and are ignored. Two nodes run: /simulator on a scene of free bodies, and
/simulator_joints on the double pendulum, which adds the manifest's publishes_with_joints.
"""
import os
import sys
import unittest

import rosgraph
import rospkg
import rospy
import rosservice
import rostest
import yaml

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import wait_until  # noqa: E402

NODE = '/simulator'
JOINTS_NODE = '/simulator_joints'  # the same node on a scene with joints


def roscpp_extras(node):
    return {'/rosout', node + '/get_loggers', node + '/set_logger_level'}


def resolve(name, node=NODE):
    return node + '/' + name[1:] if name.startswith('~') else name


class InterfaceTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('interface_test')
        cls.package = rospkg.RosPack().get_path('cga_rigid_sim')
        with open(os.path.join(cls.package, 'test', 'interface.yaml')) as f:
            cls.manifest = yaml.safe_load(f)
        cls.master = rosgraph.Master('/interface_test')
        expected_services = [resolve(s, node) for s in cls.manifest['services']
                             for node in (NODE, JOINTS_NODE)]
        # Everything is registered before the node's main loop starts; wait for the last.
        wait_until(lambda: all(rosservice.get_service_node(s) for s in expected_services),
                   what='every manifest service registered')

    def node_state(self, node):
        publishers, subscribers, services = self.master.getSystemState()

        def of_node(entries):
            return {name for name, nodes in entries if node in nodes} - roscpp_extras(node)
        return of_node(publishers), of_node(subscribers), of_node(services)

    def assertTopics(self, node, actual, manifest_entries):
        expected = {resolve(t, node): ty for t, ty in manifest_entries.items()}
        self.assertEqual(actual, set(expected), node)
        types = dict(self.master.getTopicTypes())
        for topic, ty in expected.items():
            self.assertEqual(types.get(topic), ty, topic)

    def test_published_topics_and_types(self):
        self.assertTopics(NODE, self.node_state(NODE)[0], self.manifest['publishes'])

    def test_a_scene_with_joints_also_publishes_joint_states(self):
        expected = dict(self.manifest['publishes'])
        expected.update(self.manifest['publishes_with_joints'])
        self.assertTopics(JOINTS_NODE, self.node_state(JOINTS_NODE)[0], expected)

    def test_subscribed_topics_and_types(self):
        for node in (NODE, JOINTS_NODE):
            self.assertTopics(node, self.node_state(node)[1], self.manifest['subscribes'])

    def test_services_and_types(self):
        for node in (NODE, JOINTS_NODE):
            expected = {resolve(s, node): ty for s, ty in self.manifest['services'].items()}
            _, _, services = self.node_state(node)
            self.assertEqual(services, set(expected), node)
            for service, ty in expected.items():
                self.assertEqual(rosservice.get_service_type(service), ty, service)

    def test_latched_topics_answer_a_late_subscriber(self):
        # ~rejected_inputs is latched: a subscriber that comes late still gets the count (0).
        from std_msgs.msg import UInt64
        msg = rospy.wait_for_message(NODE + '/rejected_inputs', UInt64, timeout=10.0)
        self.assertEqual(msg.data, 0)

    def test_node_reference_documents_every_entry(self):
        with open(os.path.join(self.package, 'README.md')) as f:
            readme = f.read()
        self.assertTrue('## The simulator node' in readme and '(doc/node.md)' in readme,
                        'README.md has no section "## The simulator node" linking doc/node.md')
        with open(os.path.join(self.package, 'doc', 'node.md')) as f:
            reference = f.read()
        names = (list(self.manifest['publishes']) + list(self.manifest['publishes_with_joints']) +
                 list(self.manifest['publishes_with_curvature']) +
                 list(self.manifest['subscribes']) + list(self.manifest['services']) +
                 list(self.manifest['parameters']))
        missing = [n for n in names if n.lstrip('~') not in reference]
        self.assertEqual(missing, [], 'doc/node.md does not mention these interface names')


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'interface', InterfaceTest)
