#!/usr/bin/env python3
"""ros_control controllers through the node: commands in, /<controller>/state and /joint_states
out, bad commands refused, bad configurations refused at start.

Scene: urdf/arm7.urdf with config/arm7.yaml (the arm at rest at a bent pose) and
config/arm7_controllers.yaml, as arm7.launch loads them; dt = 1 ms, paused and driven by ~step
so that every message belongs to a known step. Three nodes (controllers.test): /traj and /twin
run arm_controller (position trajectory controller) and joint_state_controller (50 Hz), /group
runs arm_group_controller (group position controller) and joint_state_controller.

Truths:
  - rates are simulation-clock ticks: /arm_controller/state at its state_publish_rate (50 Hz,
    every 20 steps) and /joint_states at the joint state controller's publish_rate (50 Hz,
    instead of the node's 100 Hz ticks), each stamp once;
  - the state's fields mean what control_msgs says: actual = /joint_states at the same stamp
    (bit for bit: both read the same joints at the same step), error = desired - actual (bit for
    bit: one subtraction), desired = the commanded point at its time (a knot of the spline, to
    1e-12: the Hermite segment evaluated at its end);
  - the trajectory is followed within the YAML's path tolerance (0.05 rad) at every state and
    reaches its goal within the goal tolerance (0.01 rad) by its end + goal_time (1 s), without
    the controller aborting (no abort warning on /rosout);
  - bad commands (a NaN position, an unknown joint, times that do not increase, a group command
    of the wrong length) are refused whole: each raises ~rejected_inputs by exactly one, is
    warned about naming <controller>/command.<field> and the rule, and changes nothing: /traj's
    joint states after them are bit-identical to /twin's, which never got them;
  - a group position command moves the arm to it and holds it there at the servo's static
    equilibrium: at rest the reported effort is p (target - q), so each joint's error is its
    effort over p (to the damping term d q' left at the residual speed, below 1e-4 rad/s), and
    under the goal tolerance with these gains (measured 0.0045 rad on joint2, 68 N m / 15000);
  - a controller configuration the World refuses ends the node at start with status 1 and a
    FATAL naming the parameter (/bad_arm/joints[6]) and the rule.
"""
import os
import sys
import threading
import time
import unittest

import rospkg
import rospy
from cga_rigid_sim.srv import SetJointState
import rostest
from cga_rigid_sim.msg import JointTrajectoryControllerState
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Simulator, joint_fields, make_trajectory,  # noqa: E402
                           start_failure, wait_until)

JOINTS = ['joint%d' % k for k in range(1, 8)]
NS_PER_STEP = 1000000
STATE_EVERY = 20        # steps between /arm_controller/state and /joint_states (50 Hz)
PATH_TOL = 0.05         # rad, constraints.<joint>.trajectory in arm7_controllers.yaml
GOAL_TOL = 0.01         # rad, constraints.<joint>.goal
GOAL_TIME = 1.0         # s, constraints.goal_time
P_GAINS = (15000.0, 15000.0, 6000.0, 6000.0, 2000.0, 2000.0, 500.0)  # gazebo_ros_control/pid_gains
D_MAX = 300.0           # N m s/rad, the largest d of pid_gains
REST_SPEED = 1e-4       # rad/s: settled, 2 s after the command (several damping times)
STATIC_TOL = D_MAX * REST_SPEED / P_GAINS[-1]  # rad: the d (0 - qd) term left in the effort


class Node(object):
    """One simulator of controllers.test with its joint states and controller topics."""

    def __init__(self, ns, group=False):
        self.sim = Simulator('/%s/simulator' % ns)
        self.lock = threading.Lock()
        self.joint_states, self.states = {}, {}
        subs = [rospy.Subscriber('/%s/joint_states' % ns, JointState, self._on_joints,
                                 queue_size=None)]
        if group:
            self.command = rospy.Publisher('/%s/arm_group_controller/command' % ns,
                                           Float64MultiArray, queue_size=10)
        else:
            self.command = rospy.Publisher('/%s/arm_controller/command' % ns, JointTrajectory,
                                           queue_size=10)
            subs.append(rospy.Subscriber('/%s/arm_controller/state' % ns,
                                         JointTrajectoryControllerState, self._on_state,
                                         queue_size=None))
        for topic in [self.command] + subs:
            wait_until(lambda: topic.get_num_connections() > 0, what=topic.name + ' connected')

    def _on_joints(self, msg):
        with self.lock:
            self.joint_states[msg.header.stamp] = msg

    def _on_state(self, msg):
        with self.lock:
            self.states[msg.header.stamp] = msg

    def step(self, n):
        """Steps n; returns the final stamp once its joint states have arrived."""
        t = self.sim.step(n)
        wait_until(lambda: t in self.joint_states, what='/joint_states at %s' % t)
        return t

    def refused(self, msg):
        """Sends a command the node must refuse and waits for ~rejected_inputs to count it."""
        before = self.sim.rejected
        self.command.publish(msg)
        self.sim.wait_rejected(before + 1)


def trajectory(points, stamp=None):
    return make_trajectory(JOINTS, points, stamp)


class ControllersTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('controllers_test')
        cls.log = []
        rospy.Subscriber('/rosout', Log, lambda m: cls.log.append(m), queue_size=None)
        cls.traj = Node('traj')
        cls.twin = Node('twin')
        cls.group = Node('group', group=True)
        time.sleep(0.5)  # /rosout connected

    def warnings(self, node, text):
        return [m.msg for m in self.log if m.name == node and m.level >= Log.WARN and text in m.msg]

    def test_a_bad_commands_change_nothing(self):
        self.traj.step(200)
        self.twin.step(200)
        q = self.traj.joint_states[max(self.traj.joint_states)].position
        nan = list(q)
        nan[1] = float('nan')
        bad = [
            (trajectory([(1.0, nan, None)]), 'arm_controller/command.points[0].positions[1]'),
            (JointTrajectory(joint_names=JOINTS[:6] + ['joint8'],
                             points=[JointTrajectoryPoint(positions=list(q),
                                                          time_from_start=rospy.Duration(1))]),
             'arm_controller/command.joint_names[6]'),
            (trajectory([(1.0, q, None), (1.0, q, None)]),
             'arm_controller/command.points[1].time_from_start'),
        ]
        for k, (msg, field) in enumerate(bad):
            if k:
                time.sleep(1.1)  # one warning a second per topic: let each one be said
            self.traj.refused(msg)
            wait_until(lambda: self.warnings('/traj/simulator', field),
                       what='a warning on ' + field)
        self.assertEqual(self.traj.sim.rejected, 3)
        t = self.traj.step(300)
        self.assertEqual(self.twin.step(300), t)
        self.assertEqual(joint_fields(self.traj.joint_states[t]),
                         joint_fields(self.twin.joint_states[t]))
        self.assertEqual(self.twin.sim.rejected, 0)

    def test_b_trajectory_within_tolerances(self):
        node = self.traj
        t0 = node.sim.time()
        q0 = node.joint_states[t0].position
        q2 = [a + d for a, d in zip(q0, (0.4, -0.3, 0.3, 0.4, -0.4, 0.4, 0.5))]
        q1 = [(a + b) / 2 for a, b in zip(q0, q2)]
        v1 = [(b - a) / 2.0 for a, b in zip(q0, q2)]  # rad/s: the mean speed over the 2 s
        node.command.publish(trajectory([(1.0, q1, v1), (2.0, q2, [0.0] * 7)]))  # stamp 0: now
        # Refused after it on the same connection: once counted, the trajectory is queued for
        # the next step, t0.
        node.refused(JointTrajectory())
        steps = int(round((2.0 + GOAL_TIME) * 1000))
        t_end = node.step(steps)
        # The states up to t_end arrive in order on one connection: wait for the last.
        wait_until(lambda: t_end in node.states, what='/traj/arm_controller/state at the end')
        window = [s for s in sorted(node.states) if t0 < s <= t_end]
        self.assertEqual(len(window), steps // STATE_EVERY)
        for a, b in zip([t0] + window, window):
            self.assertEqual((b - a).to_nsec(), STATE_EVERY * NS_PER_STEP)
        joints_window = [s for s in sorted(node.joint_states) if t0 < s <= t_end]
        self.assertEqual(joints_window, window, '/joint_states at the 50 Hz of the controller')
        worst = 0.0
        for s in window:
            st = node.states[s]
            self.assertEqual(list(st.joint_names), JOINTS)
            self.assertEqual(st.actual.positions, node.joint_states[s].position)
            self.assertEqual(st.actual.velocities, node.joint_states[s].velocity)
            self.assertEqual(list(st.error.positions),
                             [d - a for d, a in zip(st.desired.positions, st.actual.positions)])
            worst = max(worst, max(abs(e) for e in st.error.positions))
        self.assertLessEqual(worst, PATH_TOL)
        knot = node.states[t0 + rospy.Duration(1.0)]
        for d, q in zip(knot.desired.positions, q1):
            self.assertAlmostEqual(d, q, delta=1e-12)
        final = node.joint_states[t_end].position
        goal_error = max(abs(a - b) for a, b in zip(final, q2))
        self.assertLessEqual(goal_error, GOAL_TOL)
        self.assertEqual(self.warnings('/traj/simulator', 'aborted'), [])
        rospy.loginfo('trajectory: %d states at 50 Hz, worst path error %.3g rad (tolerance %g), '
                      'goal error %.3g rad (tolerance %g)', len(window), worst, PATH_TOL,
                      goal_error, GOAL_TOL)

    def test_c_group_position_command(self):
        node = self.group
        t0 = node.step(100)
        q0 = node.joint_states[t0].position
        target = [a + d for a, d in zip(q0, (-0.3, 0.2, 0.3, -0.2, 0.3, -0.3, 0.4))]
        node.command.publish(Float64MultiArray(data=target))
        # Refused after it on the same connection: once counted, the good one has been taken.
        node.refused(Float64MultiArray(data=target[:6]))
        node.refused(Float64MultiArray(data=target[:6] + [float('inf')]))
        self.assertEqual(node.sim.rejected, 2)
        t = node.step(2000)
        js = node.joint_states[t]
        self.assertLess(max(abs(v) for v in js.velocity), REST_SPEED, 'the arm has settled')
        # At rest the servo's effort is p (target - q): the static error is effort / p.
        worst = 0.0
        for joint, q, r, effort, p in zip(JOINTS, js.position, target, js.effort, P_GAINS):
            self.assertAlmostEqual(r - q, effort / p, delta=STATIC_TOL, msg=joint)
            worst = max(worst, abs(r - q))
        self.assertLess(worst, GOAL_TOL)
        rospy.loginfo('group position command: static error %.3g rad = effort / p', worst)

    def test_cz_set_joint_state(self):
        """~set_joint_state sets a joint at its step, and the group controller holds it there."""
        node = self.group
        t0 = node.step(10)
        srv = rospy.ServiceProxy('/group/simulator/set_joint_state', SetJointState)
        srv.wait_for_service(timeout=10)
        req = JointState(name=['joint3'], position=[0.6])
        req.header.stamp = t0 + rospy.Duration(0.005)  # five steps ahead: a stamped edit
        self.assertTrue(srv(req).success)
        before = node.sim.rejected
        bad = srv(JointState(name=['joint3'], position=[9.0]))
        self.assertFalse(bad.success)
        self.assertIn('set_joint_state.position[0]', bad.message)
        self.assertIn('outside the limits', bad.message)
        node.sim.wait_rejected(before + 1)
        t = node.step(6)
        js = node.joint_states[t]
        # Set at the step of its stamp, then one step of the held servo: within a step's motion.
        self.assertAlmostEqual(js.position[2], 0.6, delta=1e-3)
        t = node.step(2000)
        js = node.joint_states[t]
        # Held where it was set (the servo's static error, effort / p, aside).
        self.assertAlmostEqual(js.position[2] + js.effort[2] / P_GAINS[2], 0.6, delta=STATIC_TOL)

    def test_d_refused_configuration_ends_the_node(self):
        urdf = os.path.join(rospkg.RosPack().get_path('cga_rigid_sim'), 'urdf', 'arm7.urdf')
        rospy.set_param('/bad_arm', {'type': 'position_controllers/JointTrajectoryController',
                                     'joints': JOINTS[:6] + ['joint9']})
        status, out = start_failure('bad_controllers', '_urdf_file:=' + urdf,
                                    '_controllers:=bad_arm')
        self.assertEqual(status, 1, out)
        self.assertIn("/bad_arm/joints[6]: unknown joint 'joint9'", out)
        status, out = start_failure('bad_controllers', '_urdf_file:=' + urdf,
                                    '_controllers:=[bad_arm, no_such_controller]')
        self.assertEqual(status, 1, out)
        self.assertIn('/no_such_controller: no controller of that name', out)
        self.assertIn('bad_arm', out)
        status, out = start_failure('bad_controllers', '_urdf_file:=' + urdf, '_controllers:=3')
        self.assertEqual(status, 1, out)
        self.assertIn('~controllers: expected a list of controller names', out)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'controllers', ControllersTest)
