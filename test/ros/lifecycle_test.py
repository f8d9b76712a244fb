#!/usr/bin/env python3
"""The node fails loudly on a bad start and stops promptly on Ctrl-C.

Truths (the contract of the node's process):
  - a scene that cannot be loaded, a missing URDF or a bad parameter ends the node with exit
    status 1 and a FATAL message naming the problem (the loader's message);
  - SIGINT (Ctrl-C) ends a running node within 1 s with status 0 — running in real time,
    running as fast as possible, paused, and in the middle of a long ~step call;
  - running as fast as possible, the node still answers services promptly;
  - asked for a real-time factor it cannot reach, it warns once, with the factor it achieves.
The test starts its own simulator processes (rosrun-style) against the rostest master.
"""
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import rospy
import rostest
from cga_rigid_sim.srv import Step

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import start_failure, start_simulator, wait_until  # noqa: E402
import rosservice  # noqa: E402

URDF = os.path.join(os.path.dirname(os.path.realpath(__file__)), 'bodies.urdf')
SHUTDOWN_LIMIT = 1.0  # s


class LifecycleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('lifecycle_test')
        cls.count = 0

    def start(self, *args):
        LifecycleTest.count += 1
        name = 'sim_%d' % LifecycleTest.count
        return name, start_simulator(name, *args)

    def assertFailsToStart(self, expected_text, *args):
        LifecycleTest.count += 1
        status, out = start_failure('sim_%d' % LifecycleTest.count, *args)
        self.assertEqual(status, 1, out)
        self.assertIn('FATAL', out)
        self.assertIn(expected_text, out)

    def assertStopsOnSigint(self, name, proc, before_signal=None):
        wait_until(lambda: rosservice.get_service_node('/%s/step' % name), what=name + ' up')
        time.sleep(0.3)
        if before_signal:
            before_signal(name)
        start = time.time()
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=10.0)
        elapsed = time.time() - start
        rospy.loginfo('%s stopped %.3f s after SIGINT', name, elapsed)
        self.assertEqual(proc.returncode, 0, out)
        self.assertLess(elapsed, SHUTDOWN_LIMIT)

    def test_unloadable_scene_exits_1_with_the_loaders_message(self):
        with tempfile.NamedTemporaryFile('w', suffix='.urdf', delete=False) as f:
            f.write('<robot name="broken"><link name="a">')
            path = f.name
        self.assertFailsToStart(path, '_urdf_file:=' + path)
        self.assertFailsToStart('/no/such/file.urdf', '_urdf_file:=/no/such/file.urdf')

    def test_missing_urdf_exits_1(self):
        self.assertFailsToStart('robot_description')

    def test_bad_parameters_exit_1(self):
        self.assertFailsToStart('~dt', '_urdf_file:=' + URDF, '_dt:=fast')
        self.assertFailsToStart('dt', '_urdf_file:=' + URDF, '_dt:=-0.001')
        self.assertFailsToStart('no_such_integrator', '_urdf_file:=' + URDF,
                                '_integrator:=no_such_integrator')
        self.assertFailsToStart('~real_time_factor', '_urdf_file:=' + URDF,
                                '_real_time_factor:=-1.0')

    def test_sigint_stops_a_real_time_node_within_1_s(self):
        self.assertStopsOnSigint(*self.start('_urdf_file:=' + URDF))

    def test_sigint_stops_an_as_fast_as_possible_node_within_1_s(self):
        self.assertStopsOnSigint(*self.start('_urdf_file:=' + URDF, '_real_time_factor:=0.0'))

    def test_as_fast_as_possible_still_answers_services(self):
        name, proc = self.start('_urdf_file:=' + URDF, '_real_time_factor:=0.0')
        wait_until(lambda: rosservice.get_service_node('/%s/step' % name), what=name + ' up')
        step = rospy.ServiceProxy('/%s/step' % name, Step)
        step.wait_for_service(timeout=10.0)
        times = []
        for _ in range(10):
            start = time.time()
            t = step(0).sim_time
            times.append(time.time() - start)
        rospy.loginfo('factor 0: sim time %.1f s; ~step 0 answered in %.1f ms at worst',
                      t.to_sec(), 1e3 * max(times))
        self.assertGreater(t.to_sec(), 0.0)
        self.assertLess(max(times), 0.5)
        self.assertStopsOnSigint(name, proc)

    def test_unreachable_real_time_factor_warns_once(self):
        # The test scene rests (no gravity): steps are nearly free, but not 10^7 s per s.
        name, proc = self.start('_urdf_file:=' + URDF, '_real_time_factor:=10000000.0')
        wait_until(lambda: rosservice.get_service_node('/%s/step' % name), what=name + ' up')
        time.sleep(5.0)  # two windows of 2 s
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=10.0)
        warnings = [line for line in out.splitlines() if 'cannot keep real_time_factor' in line]
        self.assertEqual(len(warnings), 1, out)
        self.assertIn('achieved', warnings[0])

    def test_sigint_stops_a_paused_node_within_1_s(self):
        self.assertStopsOnSigint(*self.start('_urdf_file:=' + URDF, '_paused:=true'))

    def test_sigint_stops_a_long_step_call_within_1_s(self):
        def long_step(name):
            # ~step 4e9 would take hours; call it without waiting for the answer.
            subprocess.Popen(['rosservice', 'call', '/%s/step' % name, '4000000000'],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            time.sleep(1.0)
        self.assertStopsOnSigint(*self.start('_urdf_file:=' + URDF, '_paused:=true'),
                                 before_signal=long_step)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'lifecycle', LifecycleTest)
