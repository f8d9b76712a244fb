#!/usr/bin/env python3
"""An articulated tree through the node: /joint_states out, ~joint_efforts and
~apply_joint_effort in, refusals counted, tf of every link.

Scene: urdf/double_pendulum.urdf (two 1 kg rods, 1 m long, CoM at their middles, on continuous
joints about y, the shoulder 2 m above the origin), released at rest at shoulder 1.0 rad, elbow
0.5 rad (~initial_state in joints.test), gravity 9.81 m/s^2, dt = 1 ms, paused and driven by
~step so every number belongs to a known step.

Truths:
  - the potential energy on ~momentum is m g (z_upper + z_lower) with the rods' centres of mass
    placed by the joint angles of /joint_states: the positions mean what the URDF says (1e-12 J:
    a few roundings of numbers of order 30 J);
  - released, the pendulum falls back (shoulder angle decreasing at first, its velocity < 0)
    and swings through 0 within one second; the velocity is the rate of the position (central
    differences of the 100 Hz ticks: error h^2/6 |q'''| with h = 10 ms, 0.036 rad/s at worst in
    these 2 s of chaotic swing; bound 0.1 rad/s, while a wrong sign or a tick off is of the
    order of the velocities, several rad/s); the total energy kinetic + potential stays within
    1e-3 J of its initial value (no damping, no friction; measured 2.8e-5 J over 2 s at 1 ms);
  - a held shoulder effort of 150 N m against a limit of 100 N m is clamped: /joint_states
    reports 100, and the energy grows by the work of the clamped torque, 100 N m x (q_stop -
    q_start) (work-energy theorem for a constant torque), then stays (1e-3 J: the integrator's
    energy error under the torque, measured 3.5e-4 J for 16.8 J of work);
  - bad efforts (unknown joint, NaN, lengths that differ) are refused as a whole, each counted
    once in ~rejected_inputs, warned with the joint and the rule, and change nothing
    (bit-identical motion against a run without them);
  - ~apply_joint_effort acts for exactly round(duration/dt) steps from its start and shows in
    the effort field just then; an unknown joint or an infinite effort is answered
    success = false with the reason, and counted;
  - tf has every link where the joint angles put it (world -> upper, world -> lower to 1e-12:
    the node's motors and this test's rotation about y evaluate the same pose in double);
  - the `exact` integrator, which has no form for trees, ends the node with status 1 and the
    reason.
"""
import math
import os
import sys
import threading
import time
import unittest

import rospkg
import rospy
import rostest
import tf2_ros
from cga_rigid_sim.srv import ApplyJointEffort
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (TIMEOUT, Simulator, body, max_abs_diff, quat,  # noqa: E402
                           quat_distance, start_failure, vec, wait_until)

NODE = '/simulator'
DT = 0.001             # s, ~dt
TICK = 10              # steps per tick at ~publish_rate 100 Hz
NS_PER_STEP = 1000000
G = 9.81
Q0 = (1.0, 0.5)        # shoulder, elbow at release (joints.test ~initial_state)
EFFORT_LIMIT = 100.0   # N m, <limit effort> of both joints
ENERGY_TOL = 1e-3      # J


def rod_pose(q_sum, origin):
    """World pose of a link frame turned by q_sum about y at `origin` (t, q (w, x, y, z))."""
    return origin, (math.cos(q_sum / 2), 0.0, math.sin(q_sum / 2), 0.0)


def down(angle):
    """The unit vector (0, 0, -1) turned by `angle` about y."""
    return (-math.sin(angle), 0.0, -math.cos(angle))


def link_poses(q1, q2):
    """World poses of the links upper and lower from the joint angles (URDF kinematics)."""
    shoulder = (0.0, 0.0, 2.0)
    d1 = down(q1)
    elbow = tuple(s + d for s, d in zip(shoulder, d1))
    return rod_pose(q1, shoulder), rod_pose(q1 + q2, elbow)


def potential_energy(q1, q2):
    """m g (z of both centres of mass), 1 kg rods, CoM 0.5 m from their joints."""
    z1 = 2.0 - 0.5 * math.cos(q1)
    z2 = 2.0 - math.cos(q1) - 0.5 * math.cos(q1 + q2)
    return G * (z1 + z2)


class JointsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('joints_test')
        cls.lock = threading.Lock()
        cls.joint_states = {}  # stamp -> JointState
        cls.warnings = []      # texts of the node's WARN messages on /rosout
        cls.buffer = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.buffer)
        joint_states_sub = rospy.Subscriber('/joint_states', JointState, cls.on_joint_states,
                                            queue_size=None)
        rospy.Subscriber('/rosout', Log, cls.on_log, queue_size=None)
        cls.sim = Simulator()
        cls.efforts_pub = rospy.Publisher(NODE + '/joint_efforts', JointState, queue_size=100)
        rospy.wait_for_service(NODE + '/apply_joint_effort', timeout=TIMEOUT)
        cls.apply_effort = rospy.ServiceProxy(NODE + '/apply_joint_effort', ApplyJointEffort)
        wait_until(lambda: cls.efforts_pub.get_num_connections() > 0,
                   what='~joint_efforts connected')
        # The node builds /joint_states only for a subscriber it is connected to.
        wait_until(lambda: joint_states_sub.get_num_connections() > 0,
                   what='/joint_states connected')

    @classmethod
    def on_joint_states(cls, msg):
        with cls.lock:
            cls.joint_states[msg.header.stamp] = msg

    @classmethod
    def on_log(cls, msg):
        if msg.name == NODE and msg.level == Log.WARN:
            with cls.lock:
                cls.warnings.append(msg.msg)

    # ---- helpers ----
    def joints_at(self, stamp):
        wait_until(lambda: stamp in self.joint_states,
                   what='/joint_states stamped %.9f' % stamp.to_sec())
        return self.joint_states[stamp]

    def fresh_start(self):
        """Reset (every joint back to Q0, efforts dropped), then one step so the outputs at the
        current stamp show the reset state; returns that stamp."""
        self.sim.reset()
        return self.sim.step(1)

    def ahead(self, t, steps):
        return t + rospy.Duration(0, steps * NS_PER_STEP)

    def efforts(self, names, efforts, stamp=None):
        msg = JointState(name=list(names), effort=list(efforts))
        if stamp is not None:
            msg.header.stamp = stamp
        return msg

    def barrier(self):
        """Returns once the node has processed every ~joint_efforts message sent so far: sends
        one it must refuse, on the same connection, and waits for the count (costs one)."""
        before = self.sim.rejected
        self.efforts_pub.publish(self.efforts(['__barrier__'], [0.0]))
        self.sim.wait_rejected(before + 1)

    def energy(self, stamp):
        total = body(self.sim.momentum_at(stamp), 'total')
        return total.kinetic_energy + total.potential_energy

    def run_positions(self, steps):
        """The joint positions `steps` steps after a reset, with no input."""
        self.sim.reset()
        return tuple(self.joints_at(self.sim.step(steps)).position)

    # ---- outputs ----
    def test_joint_states_at_each_tick_with_every_joint(self):
        t0 = self.fresh_start()
        first = self.joints_at(t0)
        self.assertEqual(list(first.name), ['shoulder', 'elbow'])
        self.assertEqual(len(first.position), 2)
        self.assertEqual(len(first.velocity), 2)
        self.assertEqual(len(first.effort), 2)
        # At 100 Hz of simulation time: one message per 10 steps, stamped on the tick grid,
        # plus the final state of the ~step call when that is not on a tick.
        t_end = self.sim.step(100)
        self.joints_at(t_end)  # the last one sent: every earlier one has arrived (one connection)
        received = [s.to_nsec() // NS_PER_STEP for s in sorted(self.joint_states)
                    if t0 < s <= t_end]
        k0, k_end = t0.to_nsec() // NS_PER_STEP, t_end.to_nsec() // NS_PER_STEP
        expected = [k for k in range(k0 + 1, k_end + 1) if k % TICK == 0 or k == k_end]
        self.assertEqual(received, expected)
        self.assertEqual(len([k for k in received if k % TICK == 0]), 10)
        self.assertEqual(list(first.effort), [0.0, 0.0])  # no actuator commanded

    def test_initial_potential_energy_follows_the_joint_angles(self):
        t0 = self.fresh_start()
        q = self.joints_at(t0).position
        momentum = self.sim.momentum_at(t0)
        total = body(momentum, 'total')
        self.assertAlmostEqual(total.potential_energy, potential_energy(*q), delta=1e-12)
        # The tree's own entry, named after its first link, sits before the total and carries
        # the same energy here (the pendulum is the scene's only tree).
        tree = body(momentum, 'tree:upper')
        self.assertEqual([b.body for b in momentum.bodies][-2:], ['tree:upper', 'total'])
        self.assertAlmostEqual(tree.potential_energy, potential_energy(*q), delta=1e-12)

    def test_released_pendulum_swings_through_zero_and_keeps_its_energy(self):
        # One step after the release the energy is still the release's (it is conserved).
        t0 = self.fresh_start()
        e0 = self.energy(t0)
        self.assertAlmostEqual(e0, potential_energy(*Q0), delta=1e-3)
        t_end = self.sim.step(2000)  # 2 s
        self.joints_at(t_end)  # the last one sent: every earlier one has arrived
        stamps = [s for s in sorted(self.joint_states)
                  if t0 < s <= t_end and (s.to_nsec() // NS_PER_STEP) % TICK == 0]
        self.assertEqual(len(stamps), 200)
        q1 = [self.joint_states[s].position[0] for s in stamps]
        v1 = [self.joint_states[s].velocity[0] for s in stamps]
        # Falls back first, through 0 within 1 s.
        self.assertLess(q1[0], Q0[0])
        self.assertLess(v1[0], 0.0)
        crossing = next((k for k in range(1, len(q1)) if q1[k - 1] > 0.0 >= q1[k]), None)
        self.assertIsNotNone(crossing, 'the shoulder never swung through 0 in 2 s')
        self.assertLess((stamps[crossing] - t0).to_sec(), 1.0)
        # The velocity is the rate of the position.
        h = TICK * DT
        for k in range(1, len(stamps) - 1):
            for j in range(2):
                rate = (self.joint_states[stamps[k + 1]].position[j] -
                        self.joint_states[stamps[k - 1]].position[j]) / (2 * h)
                self.assertLess(abs(rate - self.joint_states[stamps[k]].velocity[j]), 0.1,
                                'joint %d at %.3f s' % (j, stamps[k].to_sec()))
        # Energy conserved at every tick.
        worst = max(abs(self.energy(s) - e0) for s in stamps)
        worst_rate = max(abs((self.joint_states[stamps[k + 1]].position[j] -
                              self.joint_states[stamps[k - 1]].position[j]) / (2 * h) -
                             self.joint_states[stamps[k]].velocity[j])
                         for k in range(1, len(stamps) - 1) for j in range(2))
        rospy.loginfo('double pendulum: worst |central difference - velocity| %.3g rad/s',
                      worst_rate)
        rospy.loginfo('double pendulum: energy %.9f J, worst change over 2 s %.3g J', e0, worst)
        self.assertLess(worst, ENERGY_TOL)

    def test_tf_has_every_link_where_the_joints_put_it(self):
        self.sim.reset()
        t = self.sim.step(137)  # not a tick: ~step publishes the final state anyway
        q = self.joints_at(t).position
        upper, lower = link_poses(*q)
        for link, expected in (('upper', upper), ('lower', lower)):
            tf = self.buffer.lookup_transform('world', link, t, rospy.Duration(10.0))
            self.assertLess(max_abs_diff(vec(tf.transform.translation), expected[0]), 1e-12,
                            link)
            self.assertLess(quat_distance(quat(tf.transform.rotation), expected[1]), 1e-12,
                            link)

    # ---- inputs ----
    def test_held_effort_is_clamped_reported_and_does_its_work(self):
        # 150 N m on the shoulder from `start`, held until a command of 0 at `stop`, 50 steps on.
        t0 = self.fresh_start()
        start, stop = self.ahead(t0, 10), self.ahead(t0, 60)
        self.efforts_pub.publish(self.efforts(['shoulder'], [150.0], stamp=start))
        self.efforts_pub.publish(self.efforts(['shoulder'], [0.0], stamp=stop))
        self.barrier()
        t_start = self.sim.step(10)
        self.assertEqual(t_start, start)
        self.assertEqual(list(self.joints_at(t_start).effort), [0.0, 0.0])  # not yet
        q_start = self.joints_at(t_start).position[0]
        e_start = self.energy(t_start)

        t_stop = self.sim.step(50)
        js = self.joints_at(t_stop)
        self.assertEqual(list(js.effort), [EFFORT_LIMIT, 0.0])  # 150 clamped to the limit
        work = EFFORT_LIMIT * (js.position[0] - q_start)
        self.assertGreater(work, 1.0)  # it pushed the shoulder forward, against the fall

        # From `stop` on the effort is 0 and the energy stays what the work made it.
        t_end = self.sim.step(250)
        self.assertEqual(list(self.joints_at(t_end).effort), [0.0, 0.0])
        for t in (t_stop, t_end):
            gained = self.energy(t) - e_start
            rospy.loginfo('held effort: work %.9f J, energy gained %.9f J at %.3f s', work,
                          gained, t.to_sec())
            self.assertLess(abs(gained - work), ENERGY_TOL)

        # The motion differs from the free swing's.
        free = self.run_positions(1 + 10 + 50 + 250)
        self.assertGreater(abs(free[0] - self.joints_at(t_end).position[0]), 0.1)

    def wait_warning(self, text):
        wait_until(lambda: any(text in w for w in self.warnings),
                   what='a warning containing %r (got %s)' % (text, self.warnings))

    def test_bad_efforts_are_refused_by_name_counted_and_change_nothing(self):
        reference = self.run_positions(200)
        self.fresh_start()
        before = self.sim.rejected
        # Warnings are throttled to one per second per topic: let the first one through.
        time.sleep(1.1)
        bad = [
            (self.efforts(['shoulder', 'knee'], [1.0, 2.0]),
             "joint_efforts.name[1]: unknown joint 'knee'"),
            (self.efforts(['shoulder', 'elbow'], [3.0, float('nan')]),
             'joint_efforts.effort[1]: not finite (nan)'),
            (self.efforts(['shoulder', 'elbow'], [3.0]),
             'joint_efforts.effort: has 1 entries for 2 names'),
        ]
        for k, (msg, text) in enumerate(bad):
            self.efforts_pub.publish(msg)
            self.sim.wait_rejected(before + k + 1)
            self.wait_warning(text)
            time.sleep(1.1)
        positions = tuple(self.joints_at(self.sim.step(199)).position)
        self.assertEqual(positions, reference)  # bit for bit: nothing was applied

    def test_apply_joint_effort_acts_for_its_duration(self):
        t0 = self.fresh_start()
        start = self.ahead(t0, 10)
        res = self.apply_effort(joint='elbow', effort=5.0, start_time=start.to_sec(),
                                duration=0.05)
        self.assertTrue(res.success, res.message)
        self.assertEqual(self.joints_at(self.sim.step(10)).effort[1], 0.0)  # not started
        self.assertEqual(self.joints_at(self.sim.step(10)).effort[1], 5.0)
        # 50 steps from `start`: the last one is step start + 49.
        self.assertEqual(self.joints_at(self.sim.step(40)).effort[1], 5.0)
        self.assertEqual(self.joints_at(self.sim.step(10)).effort[1], 0.0)

        before = self.sim.rejected
        res = self.apply_effort(joint='knee', effort=1.0, start_time=0.0, duration=0.0)
        self.assertFalse(res.success)
        self.assertIn("apply_joint_effort.joint: unknown joint 'knee'", res.message)
        self.assertIn("'shoulder'", res.message)  # the joints it has
        self.sim.wait_rejected(before + 1)
        res = self.apply_effort(joint='elbow', effort=float('inf'), start_time=0.0,
                                duration=0.0)
        self.assertFalse(res.success)
        self.assertIn('apply_joint_effort.effort', res.message)
        self.sim.wait_rejected(before + 2)

    # ---- start-up ----
    def test_exact_integrator_is_refused_for_trees(self):
        urdf = os.path.join(rospkg.RosPack().get_path('cga_rigid_sim'), 'urdf',
                            'double_pendulum.urdf')
        status, out = start_failure('sim_exact', '_urdf_file:=' + urdf,
                                    '_integrator:=exact', '_publish_clock:=false')
        self.assertEqual(status, 1, out)
        self.assertIn('FATAL', out)
        self.assertIn('~integrator:', out)
        self.assertIn("'exact' has no form for articulated trees", out)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'joints', JointsTest)
