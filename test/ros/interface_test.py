#!/usr/bin/env python3
"""The running node offers exactly the topics and services of test/interface.yaml, with their
types, and README.md documents every entry of it.

Truth: the manifest (the public contract). The master's system state lists what the node
registered; roscpp's own ~get_loggers, ~set_logger_level and /rosout are not part of the
contract and are ignored.
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
ROSCPP_EXTRAS = {'/rosout', NODE + '/get_loggers', NODE + '/set_logger_level'}


def resolve(name):
    return NODE + '/' + name[1:] if name.startswith('~') else name


class InterfaceTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('interface_test')
        cls.package = rospkg.RosPack().get_path('cga_rigid_sim')
        with open(os.path.join(cls.package, 'test', 'interface.yaml')) as f:
            cls.manifest = yaml.safe_load(f)
        cls.master = rosgraph.Master('/interface_test')
        expected_services = [resolve(s) for s in cls.manifest['services']]
        # Everything is registered before the node's main loop starts; wait for the last.
        wait_until(lambda: all(rosservice.get_service_node(s) for s in expected_services),
                   what='every manifest service registered')

    def node_state(self):
        publishers, subscribers, services = self.master.getSystemState()

        def of_node(entries):
            return {name for name, nodes in entries if NODE in nodes} - ROSCPP_EXTRAS
        return of_node(publishers), of_node(subscribers), of_node(services)

    def test_published_topics_and_types(self):
        expected = {resolve(t): ty for t, ty in self.manifest['publishes'].items()}
        published, _, _ = self.node_state()
        self.assertEqual(published, set(expected))
        types = dict(self.master.getTopicTypes())
        for topic, ty in expected.items():
            self.assertEqual(types.get(topic), ty, topic)

    def test_subscribed_topics_and_types(self):
        expected = {resolve(t): ty for t, ty in self.manifest['subscribes'].items()}
        _, subscribed, _ = self.node_state()
        self.assertEqual(subscribed, set(expected))
        types = dict(self.master.getTopicTypes())
        for topic, ty in expected.items():
            self.assertEqual(types.get(topic), ty, topic)

    def test_services_and_types(self):
        expected = {resolve(s): ty for s, ty in self.manifest['services'].items()}
        _, _, services = self.node_state()
        self.assertEqual(services, set(expected))
        for service, ty in expected.items():
            self.assertEqual(rosservice.get_service_type(service), ty, service)

    def test_latched_topics_answer_a_late_subscriber(self):
        # ~rejected_inputs is latched: a subscriber that comes late still gets the count (0).
        from std_msgs.msg import UInt64
        msg = rospy.wait_for_message(NODE + '/rejected_inputs', UInt64, timeout=10.0)
        self.assertEqual(msg.data, 0)

    def test_readme_documents_every_entry(self):
        with open(os.path.join(self.package, 'README.md')) as f:
            readme = f.read()
        self.assertTrue('## The simulator node' in readme,
                        'README.md has no section "## The simulator node"')
        names = (list(self.manifest['publishes']) + list(self.manifest['subscribes']) +
                 list(self.manifest['services']) + list(self.manifest['parameters']))
        missing = [n for n in names if n.lstrip('~') not in readme]
        self.assertEqual(missing, [], 'README.md does not mention these interface names')


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'interface', InterfaceTest)
