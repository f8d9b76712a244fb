#!/usr/bin/env python3
"""Sensors declared in a URDF the Gazebo way, through the node (doc/sensors.md).

Scene: test/ros/sensor_bot.urdf, a 2 kg box settling on the ground plane from 1 cm up, with an
IMU link on top (yawed by pi/2), in two paused nodes /a and /b driven by ~step, ~sensor_seed 5.

Truths:
  - each sensor publishes on its plugin's topic at its update rate on the simulation clock: the
    IMU (100 Hz) every 10 steps, ground truth (50 Hz) every 20, the noisy IMU (rate 0) every
    step; each stamp once, stamps in simulation time;
  - the IMU resting on the ground reads +g up in its axes (0, 0, 9.81) once the box has settled
    (to 1e-4 m/s^2: the resting contact's residual), its angular velocity 0, its orientation the
    yaw of its <origin> (to 1e-6);
  - ground truth: frame world, child box, pose = ~get_body_state's at the same step (the same
    state, to float rounding of the message: 1e-12);
  - the bumper lists the box's contacts, the box always side a;
  - the noisy IMU's samples are a function of the seed, the sensor, the step and the sample
    index only: /b, listened to only from step 300, publishes at steps 300..400 exactly the
    values /a published at the same stamps (bit for bit), and its noise has the declared size
    (the mean of the x channel's error over 100 samples within 5 sigma/sqrt(100) of 0 and its
    spread within a factor 2 of 0.5);
  - the rover (urdf/rover.urdf, its skid-steer drive declared the Gazebo way): at rest its
    velocity servos hold it (ground truth moves < 1 mm in 0.5 s); cmd_vel (0.5 m/s forward)
    drives it at 0.5 m/s (2 %) after 1.5 s, /odom (the skid steer reports the true pose, as the
    plugin does) equals /ground_truth/odom at the same stamp (1e-9), and /imu reads +g up
    (0.2 m/s^2: the chassis rides on its wheels' contacts) once at cruise;
  - the rover spawned under the namespace r1 (~spawn_urdf) 2 m off the origin brings its
    sensors and drive: r1/cmd_vel (0.5 m/s) drives it at 0.5 m/s (2 %) after 1.5 s, its
    r1/odom (frame r1/odom, child r1/base_footprint) equals its r1/ground_truth/odom (1e-9),
    its r1/imu (frame r1/chassis) reads +g up (0.2 m/s^2), /tf_static places r1/odom at the
    world frame (the skid steer's odometry is the true pose: identity, 1e-12); ~delete_body r1
    unadvertises its topics; the same rover with a diff drive (wheelAcceleration 0.5 m/s^2,
    encoder odometry) as r2: a t after the command, its odometry from its start (1 cm);
  - the force-torque sensor at the shoulder of an arm at rest (test/ros/ft_arm.urdf) publishes
    geometry_msgs/WrenchStamped every 10 steps, frame the upper arm, with the weight below,
    (0, 0, 3 g) N, and its moment about the shoulder, (0, -1.4 g, 0) N m (1e-9: at rest the
    momenta change only by rounding).
"""
import math
import os
import sys
import threading
import unittest

import rosgraph
import rospy
import rostest
import tf2_ros
from cga_rigid_sim.msg import ContactArray
from geometry_msgs.msg import Pose, Twist, WrenchStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import Simulator, wait_until  # noqa: E402

G = 9.81
NS = 1000000  # ns per step


class Listener(object):
    """Messages of one topic by stamp."""

    def __init__(self, topic, kind):
        self.lock = threading.Lock()
        self.by_stamp = {}
        self.sub = rospy.Subscriber(topic, kind, self._on, queue_size=None)
        wait_until(lambda: self.sub.get_num_connections() > 0, what=topic + ' connected')

    def _on(self, msg):
        with self.lock:
            assert msg.header.stamp not in self.by_stamp, 'stamp sent twice'
            self.by_stamp[msg.header.stamp] = msg

    def at(self, stamp):
        wait_until(lambda: stamp in self.by_stamp, what='%s at %s' % (self.sub.name, stamp))
        return self.by_stamp[stamp]

    def stamps(self):
        with self.lock:
            return sorted(self.by_stamp)


def drive_forward(cmd, speed=0.5):
    """A zero command, then `speed` m/s forward, on a drive's cmd_vel publisher; the paused node
    services its callbacks meanwhile, so the command is in before the next ~step."""
    cmd.publish(Twist())
    forward = Twist()
    forward.linear.x = speed
    cmd.publish(forward)
    rospy.sleep(0.5)


def drive_topics(prefix):
    """(ground truth, odometry, IMU) listeners and the cmd_vel publisher of a rover whose topics
    start with `prefix`."""
    truth = Listener(prefix + 'ground_truth/odom', Odometry)
    odom = Listener(prefix + 'odom', Odometry)
    imu = Listener(prefix + 'imu', Imu)
    cmd = rospy.Publisher(prefix + 'cmd_vel', Twist, queue_size=10)
    wait_until(lambda: cmd.get_num_connections() > 0, what=prefix + 'cmd_vel connected')
    return truth, odom, imu, cmd


class Sensors(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('sensors_test', anonymous=True)
        cls.a = Simulator('/a/simulator')
        cls.b = Simulator('/b/simulator')
        cls.imu = Listener('/a/imu', Imu)
        cls.noisy_a = Listener('/a/noisy_imu', Imu)
        cls.truth = Listener('/a/ground_truth', Odometry)
        cls.bumper = Listener('/a/bumper', ContactArray)
        # Stepped in bursts of 50 that the every-step topics are read out of before the next:
        # the node's publishers queue 100 messages, and a burst longer than that outruns a
        # subscriber on a loaded machine (ROS drops the oldest).
        cls.burst(cls.a, 300, cls.noisy_a)
        cls.b.step(300)
        cls.noisy_b = Listener('/b/noisy_imu', Imu)
        cls.end = cls.burst(cls.a, 100, cls.noisy_a)
        cls.burst(cls.b, 100, cls.noisy_b)

    @staticmethod
    def burst(sim, steps, listener, size=50):
        """Steps `sim` by `steps` in bursts of `size`, each read out of `listener` (a topic
        published every step) before the next; returns the last stamp."""
        for _ in range(steps // size):
            end = sim.step(size)
            listener.at(end)
        return end

    def test_rates_on_the_simulation_clock(self):
        stamp = lambda s: rospy.Time(0, s * NS)  # noqa: E731
        wait_until(lambda: stamp(400) in self.imu.by_stamp, what='IMU at step 400')
        self.assertEqual(self.imu.stamps(), [stamp(s) for s in range(10, 401, 10)])
        wait_until(lambda: stamp(400) in self.truth.by_stamp, what='truth at step 400')
        self.assertEqual(self.truth.stamps(), [stamp(s) for s in range(20, 401, 20)])
        wait_until(lambda: stamp(400) in self.noisy_a.by_stamp, what='noisy IMU at 400')
        self.assertEqual(self.noisy_a.stamps(), [stamp(s) for s in range(1, 401)])

    def test_imu_at_rest_reads_plus_g_up(self):
        msg = self.imu.at(self.end)
        self.assertEqual(msg.header.frame_id, 'imu_link')
        a = msg.linear_acceleration
        self.assertLess(math.sqrt(a.x ** 2 + a.y ** 2 + (a.z - G) ** 2), 1e-4, str(a))
        w = msg.angular_velocity
        self.assertLess(math.sqrt(w.x ** 2 + w.y ** 2 + w.z ** 2), 1e-6)
        q = msg.orientation  # yaw pi/2: (0, 0, sin(pi/4), cos(pi/4)), up to sign
        dot = abs(q.z * math.sin(math.pi / 4) + q.w * math.cos(math.pi / 4))
        self.assertAlmostEqual(dot, 1.0, delta=1e-6)

    def test_ground_truth_is_the_body_state(self):
        msg = self.truth.at(self.end)
        self.assertEqual(msg.header.frame_id, 'world')
        self.assertEqual(msg.child_frame_id, 'box')
        state = self.a.get('box')
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        ps, qs = state.pose.position, state.pose.orientation
        for x, y in [(p.x, ps.x), (p.y, ps.y), (p.z, ps.z)]:
            self.assertAlmostEqual(x, y, delta=1e-12)
        self.assertAlmostEqual(abs(q.x * qs.x + q.y * qs.y + q.z * qs.z + q.w * qs.w), 1.0,
                               delta=1e-12)
        self.assertAlmostEqual(p.z, 0.05, delta=1e-3)  # resting on its 0.1 m high side

    def test_bumper_lists_the_box_contacts(self):
        msg = self.bumper.at(self.end)
        self.assertGreater(len(msg.contacts), 0)
        for c in msg.contacts:
            self.assertEqual(c.link_a, 'box')
            self.assertEqual(c.link_b, 'ground_plane')

    def test_noise_is_bit_identical_whatever_was_listened_to(self):
        stamps = [rospy.Time(0, s * NS) for s in range(301, 401)]
        errors = []
        for stamp in stamps:
            ma, mb = self.noisy_a.at(stamp), self.noisy_b.at(stamp)
            self.assertEqual(ma.linear_acceleration, mb.linear_acceleration)
            self.assertEqual(ma.angular_velocity, mb.angular_velocity)
            self.assertEqual(ma.orientation, mb.orientation)
            errors.append(ma.linear_acceleration.x - self.imu.at(self.end).linear_acceleration.x)
        mean = sum(errors) / len(errors)
        spread = math.sqrt(sum((e - mean) ** 2 for e in errors) / (len(errors) - 1))
        sigma = math.sqrt(0.5 ** 2 + 0.01 ** 2)
        self.assertLess(abs(mean), 5 * sigma / math.sqrt(len(errors)))
        self.assertTrue(sigma / 2 < spread < 2 * sigma, spread)

    def test_cmd_vel_drives_the_rover_and_odom_follows(self):
        sim = Simulator('/rover/simulator')
        truth, odom, imu, cmd = drive_topics('/')
        t0 = sim.step(500)
        x0 = truth.at(t0).pose.pose.position.x
        rested = sim.step(500)
        self.assertLess(abs(truth.at(rested).pose.pose.position.x - x0), 1e-3)
        drive_forward(cmd)  # (its zero command first: the same hold)
        end = sim.step(1500)
        t = truth.at(end)
        self.assertAlmostEqual(t.twist.twist.linear.x, 0.5, delta=0.01)
        o = odom.at(end)
        self.assertEqual(o.header.frame_id, 'odom')
        self.assertEqual(o.child_frame_id, 'base_footprint')
        for a, b in [(o.pose.pose.position.x, t.pose.pose.position.x),
                     (o.pose.pose.position.y, t.pose.pose.position.y)]:
            self.assertAlmostEqual(a, b, delta=1e-9)
        self.assertAlmostEqual(o.twist.twist.linear.x, 0.5, delta=0.01)
        a = imu.at(end).linear_acceleration
        self.assertLess(math.sqrt(a.x ** 2 + a.y ** 2 + (a.z - G) ** 2), 0.2, str(a))

    def test_force_torque_at_the_shoulder_of_an_arm_at_rest(self):
        sim = Simulator('/arm/simulator')
        ft = Listener('/arm/ft', WrenchStamped)
        end = sim.step(100)
        wait_until(lambda: end in ft.by_stamp, what='ft at step 100')
        self.assertEqual(ft.stamps(), [rospy.Time(0, s * NS) for s in range(10, 101, 10)])
        msg = ft.at(end)
        self.assertEqual(msg.header.frame_id, 'upper')
        f, t = msg.wrench.force, msg.wrench.torque
        for got, want in [(f.x, 0.0), (f.y, 0.0), (f.z, 3 * G), (t.x, 0.0), (t.y, -1.4 * G),
                          (t.z, 0.0)]:
            self.assertAlmostEqual(got, want, delta=1e-9)

    def test_a_spawned_rover_brings_its_sensors_and_drive(self):
        sim = Simulator('/spawn/simulator')
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        with open(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'urdf',
                               'rover.urdf')) as f:
            urdf = f.read()
        pose = Pose()
        pose.position.y, pose.position.z, pose.orientation.w = 2.0, 0.16, 1.0
        res = sim.spawn('rover1', urdf, pose, Twist(), 'r1')
        self.assertTrue(res.success, res.message)
        truth, odom, imu, cmd = drive_topics('/spawn/r1/')
        sim.step(500)
        drive_forward(cmd)
        end = sim.step(1500)
        t = truth.at(end)
        self.assertAlmostEqual(t.twist.twist.linear.x, 0.5, delta=0.01)
        self.assertAlmostEqual(t.pose.pose.position.y, 2.0, delta=0.05)
        o = odom.at(end)
        self.assertEqual(o.header.frame_id, 'r1/odom')
        self.assertEqual(o.child_frame_id, 'r1/base_footprint')
        for a, b in [(o.pose.pose.position.x, t.pose.pose.position.x),
                     (o.pose.pose.position.y, t.pose.pose.position.y)]:
            self.assertAlmostEqual(a, b, delta=1e-9)
        m = imu.at(end)
        self.assertEqual(m.header.frame_id, 'r1/chassis')
        a = m.linear_acceleration
        self.assertLess(math.sqrt(a.x ** 2 + a.y ** 2 + (a.z - G) ** 2), 0.2, str(a))
        anchor = buffer.lookup_transform('world', 'r1/odom', rospy.Time(0), rospy.Duration(10))
        p = anchor.transform.translation
        self.assertLess(math.sqrt(p.x ** 2 + p.y ** 2 + p.z ** 2), 1e-12)
        self.assertTrue(sim.delete('rover1').success)
        master = rosgraph.Master('/sensors_test')

        def published(topic):
            return any(name == topic for name, _ in master.getPublishedTopics('/spawn'))
        wait_until(lambda: not published('/spawn/r1/imu'), what='r1/imu unadvertised')
        self.assertFalse(published('/spawn/r1/odom'))
        self.assertFalse(published('/spawn/r1/ground_truth/odom'))

        # The same rover with a differential drive on its front axles instead (the rear wheels
        # roll free), wheelAcceleration 0.5 m/s^2 and encoder odometry, spawned as r2 at
        # (0, -2): 0.5 s after a 0.5 m/s command it moves at a t = 0.25 m/s (0.02: the servos'
        # lag and the free wheels' damping), at 0.5 m/s after 1.5 s; its odometry, in the
        # r2/odom frame that /tf_static puts at its start (0, -2, 0), follows the truth on
        # grippy ground (1 cm).
        start = urdf.index('<plugin name="skid_steer_drive"')
        end = urdf.index('</plugin>', start) + len('</plugin>')
        diff = urdf[:start] + (
            '<plugin name="diff_drive" filename="libgazebo_ros_diff_drive.so">'
            '<leftJoint>front_left_axle</leftJoint><rightJoint>front_right_axle</rightJoint>'
            '<wheelSeparation>0.5</wheelSeparation><wheelDiameter>0.2</wheelDiameter>'
            '<wheelTorque>5</wheelTorque><wheelAcceleration>0.5</wheelAcceleration>'
            '<odometrySource>encoder</odometrySource><publishOdomTF>true</publishOdomTF>'
            '</plugin>') + urdf[end:]
        pose.position.y = -2.0
        res = sim.spawn('rover2', diff, pose, Twist(), 'r2')
        self.assertTrue(res.success, res.message)
        truth, odom, _, cmd = drive_topics('/spawn/r2/')
        sim.step(300)
        drive_forward(cmd)
        half = sim.step(500)
        self.assertAlmostEqual(truth.at(half).twist.twist.linear.x, 0.25, delta=0.02)
        end = sim.step(1000)
        t, o = truth.at(end), odom.at(end)
        self.assertAlmostEqual(t.twist.twist.linear.x, 0.5, delta=0.02)
        self.assertEqual(o.header.frame_id, 'r2/odom')
        self.assertAlmostEqual(o.pose.pose.position.x, t.pose.pose.position.x, delta=0.01)
        self.assertAlmostEqual(o.pose.pose.position.y, t.pose.pose.position.y + 2.0, delta=0.01)
        anchor = buffer.lookup_transform('world', 'r2/odom', rospy.Time(0), rospy.Duration(10))
        p = anchor.transform.translation
        self.assertLess(math.sqrt(p.x ** 2 + (p.y + 2.0) ** 2 + p.z ** 2), 1e-9)
        self.assertTrue(sim.delete('rover2').success)


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'sensors', Sensors)
