#!/usr/bin/env python3
"""Self-collision through the node: the rules decided at load, and 10 s of an arm whose links meet.

Scene: test/ros/overlapping_arm.urdf, an arm of four 1 kg boxes on a fixed base; its palm, folded
up beside the forearm, overlaps the upper arm by 10 mm at the zero pose (by construction: the
palm's joint is 0.07 m off the forearm's axis, the boxes 0.08 m wide). Released with joint rates
(3, -2, 1.5, 4) rad/s under gravity, dt = 1 ms, 10 s driven by ~step. Node /simulator runs
~self_collision auto with an SRDF that disables base-tip; /all/simulator runs `all`.

Truths:
  - auto leaves out every parent-child pair, the pair that overlaps at the start (upper-palm)
    and the SRDF's (base-tip); it keeps every other pair of the arm's five links (10 pairs less
    those 6); `all` keeps all but parent-child, so upper-palm too (~self_collision_pairs);
  - a pair left out never shows on ~contacts;
  - in `all` the arm's own links touch (the overlap of the start at least): contacts inside the
    tree are exercised;
  - energy: kinetic + potential + dissipated stays at its start value, the book closing on every
    step (the midpoint's own error over 10 s of this motion is ~1e-6 J in the unit tests; 1e-4 J
    leaves room for the node's chunking and is far below what a wrong impulse pair or a missed
    stop would make, ~0.1 J and more);
  - no joint passes its limits (+-2 rad) by more than 1e-9 rad, on any published tick;
  - no tree fault: the node logs no ERROR;
  - refused at start, naming the parameter or the file, line, link and rule: ~self_collision of
    an unknown value, an SRDF naming a link the URDF lacks, a malformed SRDF, an unreadable
    ~srdf_file.
"""
import os
import sys
import tempfile
import threading
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import Simulator, body, start_failure, wait_until  # noqa: E402

URDF = os.path.join(os.path.dirname(os.path.realpath(__file__)), 'overlapping_arm.urdf')

LINKS = ['base', 'upper', 'fore', 'palm', 'tip']
PARENT_CHILD = {('base', 'upper'), ('upper', 'fore'), ('fore', 'palm'), ('palm', 'tip')}
OVERLAPPING = {('upper', 'palm')}
SRDF_DISABLED = {('base', 'tip')}
LIMIT = 2.0
STEPS, CHUNK = 10000, 500
ENERGY_TOL = 1e-4   # J
LIMIT_TOL = 1e-9    # rad


def pair(a, b):
    return tuple(sorted((a, b), key=LINKS.index))


class Run(object):
    """One node's outputs: /joint_states (or its remap), ERROR lines on /rosout."""

    def __init__(self, node, joint_states):
        self.node = node
        self.lock = threading.Lock()
        self.joints = {}
        self.errors = []
        sub = rospy.Subscriber(joint_states, JointState, self.on_joints, queue_size=None)
        rospy.Subscriber('/rosout', Log, self.on_log, queue_size=None)
        self.sim = Simulator(node)
        wait_until(lambda: sub.get_num_connections() > 0, what=joint_states + ' connected')

    def on_joints(self, msg):
        with self.lock:
            self.joints[msg.header.stamp] = msg

    def on_log(self, msg):
        if msg.name == self.node and msg.level >= Log.ERROR:
            with self.lock:
                self.errors.append(msg.msg)

    def pairs(self):
        return {pair(*p.split()) for p in rospy.get_param(self.node + '/self_collision_pairs')}


class SelfCollisionTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('self_collision_test')
        cls.auto = Run('/simulator', '/joint_states')
        cls.all = Run('/all/simulator', '/all/joint_states')

    def test_the_rules_decided_at_load(self):
        every = {pair(a, b) for i, a in enumerate(LINKS) for b in LINKS[i + 1:]}
        self.assertEqual(self.auto.pairs(), every - PARENT_CHILD - OVERLAPPING - SRDF_DISABLED)
        self.assertEqual(self.all.pairs(), every - PARENT_CHILD)

    def run_ten_seconds(self, run):
        """Steps `run` 10 s in chunks; checks the book, the limits and the contacts' pairs on every
        chunk; returns the arm's own contact pairs seen."""
        sim = run.sim
        t0 = sim.step(1)  # (a step publishes; the book from here)
        start = body(sim.momentum_at(t0), 'total')
        E0 = start.kinetic_energy + start.potential_energy + start.dissipated_energy
        allowed = run.pairs()
        seen = set()
        worst_book = worst_past = 0.0
        for _ in range(STEPS // CHUNK):
            t = sim.step(CHUNK)
            total = body(sim.momentum_at(t), 'total')
            book = total.kinetic_energy + total.potential_energy + total.dissipated_energy - E0
            worst_book = max(worst_book, abs(book))
            self.assertLess(abs(book), ENERGY_TOL, '%s at %.3f s' % (run.node, t.to_sec()))
            wait_until(lambda: t in run.joints, what='%s joint states at %.3f' % (run.node,
                                                                                  t.to_sec()))
            with run.lock:
                ticks = list(run.joints.values())
                run.joints.clear()
            for js in ticks:
                for name, q in zip(js.name, js.position):
                    worst_past = max(worst_past, abs(q) - LIMIT)
                    self.assertLessEqual(abs(q), LIMIT + LIMIT_TOL, '%s %s' % (run.node, name))
            with sim._lock:
                contacts = list(sim.contacts.values())
                sim.contacts.clear()
            for msg in contacts:
                for c in msg.contacts:
                    if c.body_b == 'ground_plane' or c.link_a not in LINKS or \
                            c.link_b not in LINKS:
                        continue
                    p = pair(c.link_a, c.link_b)
                    self.assertIn(p, allowed, '%s: a contact of a pair left out' % run.node)
                    seen.add(p)
        with run.lock:
            self.assertEqual(run.errors, [], run.node)
        rospy.loginfo('%s: 10 s, energy book within %.1e J, limits %+.1e rad, pairs met: %s',
                      run.node, worst_book, worst_past, sorted(seen))
        return seen

    def test_auto_ten_seconds(self):
        self.run_ten_seconds(self.auto)

    def test_all_ten_seconds_with_contacts_inside_the_tree(self):
        seen = self.run_ten_seconds(self.all)
        self.assertIn(('upper', 'palm'), seen)

    def assertRefused(self, name, expected, *args):
        status, out = start_failure(name, '_urdf_file:=' + URDF, *args)
        self.assertEqual(status, 1, out)
        self.assertIn('FATAL', out)
        self.assertIn(expected, out)

    def test_bad_rules_are_refused_at_start(self):
        self.assertRefused('bad_mode', "~self_collision: must be auto, all or none (got "
                           "'sometimes')", '_self_collision:=sometimes')
        with tempfile.TemporaryDirectory() as d:
            unknown = os.path.join(d, 'unknown_link.srdf')
            with open(unknown, 'w') as f:
                f.write('<robot name="arm">\n'
                        '  <disable_collisions link1="base" link2="gripper" reason="Never"/>\n'
                        '</robot>\n')
            self.assertRefused('bad_link', "srdf '%s':2: <disable_collisions> link2 'gripper': "
                               "the URDF has no link of that name" % unknown,
                               '_srdf_file:=' + unknown)
            malformed = os.path.join(d, 'malformed.srdf')
            with open(malformed, 'w') as f:
                f.write('<robot name="arm">\n  <disable_collisions link1="base"\n</robot>\n')
            self.assertRefused('bad_xml', "srdf '%s':" % malformed, '_srdf_file:=' + malformed)
            self.assertRefused('bad_xml2', 'malformed XML', '_srdf_file:=' + malformed)
            missing = os.path.join(d, 'missing.srdf')
            self.assertRefused('bad_file', "~srdf_file: cannot read '%s'" % missing,
                               '_srdf_file:=' + missing)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'self_collision', SelfCollisionTest)
