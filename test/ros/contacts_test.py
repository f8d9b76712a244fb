#!/usr/bin/env python3
"""Contacts through the node: ~ground_plane, ~contacts, the dissipated energy, and refusals.

Truths:
  - a ball (radius R = 0.1 m, mass m = 1 kg, test/ros/ball.urdf) dropped from h = 0.5 m onto the
    plane z = 0 with restitution 0 comes to rest on it: its centre at z = R, one contact per
    step that names the ball and "ground_plane", with the plane's normal (0, 0, 1) exactly, at
    z = 0, and a normal impulse that carries the ball's weight for one step, m g dt (momentum
    balance of a body at rest: the impulse cancels what gravity adds in the step);
  - energy: kinetic + potential + dissipated = the initial potential energy m g h (the contacts
    take out what the ball loses, and ~momentum reports it on "total");
  - determinism: two nodes with the same scene, the same stamped inputs and the same number of
    steps (in different ~step chunks) have bit-identical states and contacts;
  - bad contact parameters (wrong type, out of range, unknown key) end the node at start with a
    FATAL naming the parameter; ~ground_plane given as a string (rosrun's _ground_plane:={...})
    is read like the dictionary.
Until the contact solver is in, the ball falls through the plane: the first two fail on "no
contact", and the parameter cases pass.
"""
import os
import signal
import sys
import unittest

import rospy
import rosservice
import rostest

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import (Simulator, body, make_impulse, norm, start_failure,  # noqa: E402
                           start_simulator, state_fields, vec, wait_until)

URDF = os.path.join(os.path.dirname(os.path.realpath(__file__)), 'ball.urdf')
BALL = 'ball'         # body and link of ball.urdf
PLANE = 'ground_plane'
MASS, RADIUS, HEIGHT = 1.0, 0.1, 0.5  # kg, m, m (the ball's centre at the start)
G = 9.81              # m/s^2, the node's default ~gravity
DT = 0.001            # s, the node's default ~dt
NS_PER_STEP = 1000000
# The fall of h - R = 0.4 m takes sqrt(2 * 0.4 / g) = 0.29 s; with restitution 0 the ball stops
# at the impact. 2 s leave it ample time to settle.
SETTLE_STEPS = 2000
CHECKED_STEPS = 10    # single steps checked at rest
# A resting ball sinks per step by g dt^2 = 1e-5 m before its contact impulse stops it, and the
# solver removes penetration instead of letting it grow, so the resting penetration is a small
# multiple of 1e-5 m, a fraction of a mm. 1e-3 m (1 % of the radius) holds any such correction.
POSITION_TOL = 1e-3   # m
IMPULSE_REL_TOL = 0.01
# Energy: the impact's step ascribes gravity's work m g v dt (v = sqrt(2 g 0.4) = 2.8 m/s:
# 0.027 J) to before or after the impulse, and the resting penetration moves the potential
# energy by at most m g POSITION_TOL = 0.0098 J: 0.037 J in all, inside 1 % of m g h (0.049 J).
ENERGY_TOL = 0.01 * MASS * G * HEIGHT


def at_step(k):
    return rospy.Time(0, k * NS_PER_STEP)


def contact_fields(c):
    """Every field of a Contact, for bit-for-bit comparisons."""
    return ((c.body_a, c.link_a, c.body_b, c.link_b) + vec(c.position) + vec(c.normal) +
            (c.depth, c.normal_impulse) + vec(c.friction_impulse))


class ContactsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('contacts_test')
        cls.sim = Simulator()
        cls.twins = [Simulator('/twin_a/simulator'), Simulator('/twin_b/simulator')]
        cls.count = 0

    def test_a_ball_in_free_fall_has_no_contact_and_keeps_its_energy(self):
        # One step after the release: no contact 0.4 m above the plane, nothing dissipated, and
        # kinetic + potential = m g h (the flight is the exact parabola: round-off only; 1e-12 J
        # is some 200 ulp of 4.9 J).
        sim = self.sim
        sim.reset()
        t = sim.step(1)
        total = body(sim.momentum_at(t), 'total')
        self.assertEqual(sim.contacts_at(t).contacts, [])
        self.assertEqual(total.dissipated_energy, 0.0)
        self.assertAlmostEqual(total.kinetic_energy + total.potential_energy,
                               MASS * G * HEIGHT, delta=1e-12)

    def test_a_dropped_ball_rests_on_the_plane(self):
        sim = self.sim
        e0 = MASS * G * HEIGHT
        sim.reset()
        sim.step(SETTLE_STEPS)
        for _ in range(CHECKED_STEPS):
            t = sim.step(1)
            msg = sim.contacts_at(t)
            momentum = sim.momentum_at(t)
            ball = sim.get(BALL)
            self.assertEqual(msg.header.stamp, t)
            self.assertEqual(msg.header.frame_id, 'world')
            self.assertEqual(len(msg.contacts), 1,
                             'one contact of the ball with the plane at t = %.3f s (the ball is '
                             'at z = %.4f m)' % (t.to_sec(), ball.com.z))
            c = msg.contacts[0]
            self.assertEqual((c.body_a, c.link_a, c.body_b, c.link_b), (BALL, BALL, PLANE, PLANE))
            # The plane's normal is exact: no round-off enters it.
            self.assertLess(max(abs(c.normal.x), abs(c.normal.y), abs(c.normal.z - 1.0)), 1e-9)
            self.assertLess(abs(c.position.z), POSITION_TOL)
            self.assertLess(abs(c.depth), POSITION_TOL)
            self.assertLess(abs(ball.com.z - RADIUS), POSITION_TOL)
            self.assertLess(abs(c.normal_impulse - MASS * G * DT), IMPULSE_REL_TOL * MASS * G * DT)
            # The ball moves only along z and the normal is exactly z: nothing for friction.
            self.assertLess(norm(vec(c.friction_impulse)), 1e-9)

            total = body(momentum, 'total')
            self.assertEqual(body(momentum, BALL).dissipated_energy, 0.0)
            self.assertGreater(total.dissipated_energy, 0.0)
            balance = total.kinetic_energy + total.potential_energy + total.dissipated_energy
            self.assertLess(abs(balance - e0), ENERGY_TOL,
                            'kinetic %.6f + potential %.6f + dissipated %.6f J != m g h = %.6f J'
                            % (total.kinetic_energy, total.potential_energy,
                               total.dissipated_energy, e0))
        rospy.loginfo('at rest: z %.6f m, depth %.2e m, normal impulse %.6e N s (m g dt %.6e), '
                      'dissipated %.6f J, balance error %.2e J', ball.com.z, c.depth,
                      c.normal_impulse, MASS * G * DT, total.dissipated_energy, balance - e0)

    def test_the_same_inputs_give_bit_identical_states_with_contacts(self):
        # The twins: a ball thrown sideways with spin onto a bouncy plane (it bounces, slides
        # and rolls); two impulses, one in flight and one on the ground, off the centre.
        a, b = self.twins
        for sim in self.twins:
            sim.impulse_pub.publish(make_impulse(BALL, (0.2, -0.1, 0.0), point=(0.0, 0.05, 0.0),
                                                 frame=BALL, stamp=at_step(100)))
            sim.impulse_pub.publish(make_impulse(BALL, (-0.5, 0.2, 0.0), point=(0.0, 0.0, 0.08),
                                                 frame=BALL, stamp=at_step(1500)))
            sim.barrier(sim.impulse_pub)
        steps = 3000
        t_a = a.step(steps)
        t_b = None
        for chunk in [1, 9, 90, 400, 500, 2000]:
            t_b = b.step(chunk)
        self.assertEqual(t_a, t_b)
        self.assertEqual(t_a, at_step(steps))

        # The last messages came after all others on their connections: none is still coming.
        last_a, last_b = a.contacts_at(t_a), b.contacts_at(t_b)
        self.assertEqual(state_fields(a.get(BALL)), state_fields(b.get(BALL)))
        self.assertEqual([contact_fields(c) for c in last_a.contacts],
                         [contact_fields(c) for c in last_b.contacts])
        self.assertEqual(body(a.momentum_at(t_a), 'total').dissipated_energy,
                         body(b.momentum_at(t_b), 'total').dissipated_energy)
        # Not vacuous: the run had contacts.
        touched = [s for s, m in a.contacts.items() if m.contacts]
        self.assertTrue(touched, 'no contact in %d steps of a ball thrown onto the plane' % steps)
        # Every tick both published (b's chunks end on ticks but the first) is identical too.
        for stamp in sorted(set(a.contacts) & set(b.contacts)):
            self.assertEqual([contact_fields(c) for c in a.contacts[stamp].contacts],
                             [contact_fields(c) for c in b.contacts[stamp].contacts],
                             'contacts at %.3f s' % stamp.to_sec())
        rospy.loginfo('twins: %d steps, contacts at %d ticks, states bit-identical', steps,
                      len(touched))

    # ---- parameters (each case starts its own node, rosrun-style) ----

    def name(self):
        ContactsTest.count += 1
        return 'contact_params_%d' % ContactsTest.count

    def assertFailsToStart(self, expected_text, *args):
        status, out = start_failure(self.name(), '_urdf_file:=' + URDF, *args)
        self.assertEqual(status, 1, out)
        self.assertIn('FATAL', out)
        self.assertIn(expected_text, out)

    def test_bad_contact_parameters_are_refused_at_start(self):
        # Out of range: the core's rules, named as the node's parameters.
        self.assertFailsToStart('~contact_mu: must be finite and >= 0', '_contact_mu:=-1.0')
        self.assertFailsToStart('~contact_restitution: must be in [0, 1]',
                                '_contact_restitution:=1.5')
        self.assertFailsToStart('~ground_plane.mu: must be finite and >= 0',
                                '_ground_plane:={height: 0.0, mu: -0.1}')
        self.assertFailsToStart('~ground_plane.restitution: must be in [0, 1]',
                                '_ground_plane:={restitution: 2.0}')
        # Wrong types and unknown keys: the node's own reading.
        self.assertFailsToStart('~contact_mu: expected a number, got string', '_contact_mu:=high')
        self.assertFailsToStart('~ground_plane.friction: unknown key (known: height, mu, '
                                'restitution)', '_ground_plane:={height: 0.0, friction: 1.0}')
        self.assertFailsToStart('~ground_plane.height: expected a number, got string',
                                '_ground_plane:={height: low}')
        self.assertFailsToStart('~ground_plane: expected a dictionary such as {height: 0.0',
                                '_ground_plane:=[0.0, 0.0]')
        self.assertFailsToStart('~ground_plane: expected a dictionary such as {height: 0.0',
                                '_ground_plane:=0.0')

    def test_a_ground_plane_given_as_a_string_is_read(self):
        name = self.name()
        proc = start_simulator(name, '_urdf_file:=' + URDF, '_paused:=true',
                               '_publish_clock:=false', '_ground_plane:={height: -0.25, mu: 0.8}',
                               '_contact_restitution:=0.3')
        try:
            wait_until(lambda: rosservice.get_service_node('/%s/step' % name), what=name + ' up')
        finally:
            proc.send_signal(signal.SIGINT)
            out, _ = proc.communicate(timeout=10.0)
        self.assertEqual(proc.returncode, 0, out)
        self.assertIn('ground plane at z = -0.25 m (mu 0.8, restitution 0.3)', out)
        self.assertNotIn('unknown parameter', out)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'contacts', ContactsTest)
