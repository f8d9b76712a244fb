"""Helpers shared by the rostest nodes of cga_rigid_sim (test/ros/*_test.py).

A test script imports this module after putting its own directory on sys.path (catkin runs the
scripts through relays in the devel space, with __file__ naming the source file).
Every wait is on the wall clock with a timeout, so a broken node fails a test instead of
hanging it; tests drive time with ~step (paused) wherever exact numbers are checked.
"""
import math
import os
import signal
import subprocess
import threading
import time

import rosgraph
import roslib.packages
import rospy
from cga_rigid_sim.msg import BodyStateArray, CgaImpulse, CgaWrench, ContactArray, MomentumArray
from cga_rigid_sim.srv import DeleteBody, GetBodyState, SetBodyState, SpawnUrdf, Step
from geometry_msgs.msg import WrenchStamped
from std_msgs.msg import UInt64
from std_srvs.srv import Empty
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

TIMEOUT = 20.0  # s of wall time for any single wait
BARRIER = '__barrier__'  # a body and frame name no scene has


def wait_until(predicate, timeout=TIMEOUT, what='condition', period=0.01):
    """Polls `predicate` (wall clock) until it is true; fails with `what` on timeout."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(period)
    raise AssertionError('timed out after %.1f s waiting for %s' % (timeout, what))


class Simulator(object):
    """Client of one simulator node (services, input publishers, output subscribers)."""

    def __init__(self, node='/simulator'):
        self.node = node
        for name in ['step', 'pause', 'unpause', 'reset', 'clear_wrenches', 'get_body_state',
                     'set_body_state', 'spawn_urdf', 'delete_body']:
            rospy.wait_for_service(node + '/' + name, timeout=TIMEOUT)
        self._step = rospy.ServiceProxy(node + '/step', Step)
        self._pause = rospy.ServiceProxy(node + '/pause', Empty)
        self._unpause = rospy.ServiceProxy(node + '/unpause', Empty)
        self._reset = rospy.ServiceProxy(node + '/reset', Empty)
        self._clear = rospy.ServiceProxy(node + '/clear_wrenches', Empty)
        self._get = rospy.ServiceProxy(node + '/get_body_state', GetBodyState)
        self._set = rospy.ServiceProxy(node + '/set_body_state', SetBodyState)
        self._spawn = rospy.ServiceProxy(node + '/spawn_urdf', SpawnUrdf)
        self._delete = rospy.ServiceProxy(node + '/delete_body', DeleteBody)

        self.wrench_pub = rospy.Publisher(node + '/apply_wrench', CgaWrench, queue_size=100)
        self.impulse_pub = rospy.Publisher(node + '/apply_impulse', CgaImpulse, queue_size=100)
        self.plain_wrench_pub = rospy.Publisher(node + '/wrench', WrenchStamped, queue_size=100)

        self._lock = threading.Lock()
        self.momenta = {}       # stamp (rospy.Time) -> MomentumArray
        self.body_states = {}   # stamp -> BodyStateArray
        self.contacts = {}      # stamp -> ContactArray
        self.rejected = None    # last ~rejected_inputs count
        subscribers = [
            rospy.Subscriber(node + '/momentum', MomentumArray, self._on_momentum,
                             queue_size=None),
            rospy.Subscriber(node + '/body_states', BodyStateArray, self._on_body_states,
                             queue_size=None),
            rospy.Subscriber(node + '/contacts', ContactArray, self._on_contacts,
                             queue_size=None),
            rospy.Subscriber(node + '/rejected_inputs', UInt64, self._on_rejected,
                             queue_size=10)]
        # Connected both ways before any test sends or steps (the node builds an output only
        # when someone listens).
        for topic in [self.wrench_pub, self.impulse_pub, self.plain_wrench_pub] + subscribers:
            wait_until(lambda: topic.get_num_connections() > 0, what=topic.name + ' connected')
        wait_until(lambda: self.rejected is not None, what='latched ~rejected_inputs')

    # ---- services ----
    def step(self, n):
        """Advances n steps; returns the simulation time after them (rospy.Time)."""
        return self._step(n).sim_time

    def time(self):
        return self.step(0)

    def pause(self):
        self._pause()

    def unpause(self):
        self._unpause()

    def reset(self):
        self._reset()

    def clear_wrenches(self):
        self._clear()

    def get(self, body):
        res = self._get(body)
        assert res.success, 'get_body_state(%s) failed: %s' % (body, res.message)
        return res.state

    def get_response(self, body):
        return self._get(body)

    def set_state(self, state):
        return self._set(state)

    def spawn(self, name, urdf, pose, twist, robot_namespace=''):
        # By keyword: a request built from positional arguments must give every field.
        return self._spawn(name=name, urdf=urdf, pose=pose, twist=twist,
                           robot_namespace=robot_namespace)

    def delete(self, body):
        return self._delete(body)

    # ---- outputs ----
    def _on_momentum(self, msg):
        with self._lock:
            self.momenta[msg.header.stamp] = msg

    def _on_body_states(self, msg):
        with self._lock:
            self.body_states[msg.header.stamp] = msg

    def _on_contacts(self, msg):
        with self._lock:
            self.contacts[msg.header.stamp] = msg

    def _on_rejected(self, msg):
        self.rejected = msg.data

    def momentum_at(self, stamp, timeout=TIMEOUT):
        """The ~momentum message stamped `stamp` (waits for it)."""
        wait_until(lambda: stamp in self.momenta, timeout,
                   'momentum stamped %.9f' % stamp.to_sec())
        return self.momenta[stamp]

    def contacts_at(self, stamp, timeout=TIMEOUT):
        """The ~contacts message stamped `stamp` (waits for it)."""
        wait_until(lambda: stamp in self.contacts, timeout,
                   'contacts stamped %.9f' % stamp.to_sec())
        return self.contacts[stamp]

    def momentum_stamps_after(self, t):
        """Stamps of the ~momentum messages received so far that are later than t, sorted."""
        with self._lock:
            return sorted(s for s in self.momenta if s > t)

    def barrier(self, pub):
        """Returns once the node has processed every message sent on `pub` so far.

        Sends, on the same connection (so after them), an input the node must refuse (its body
        or frame is unknown) and waits for ~rejected_inputs to count it. Costs one refusal.
        """
        before = self.rejected
        if pub is self.plain_wrench_pub:
            msg = WrenchStamped()
            msg.header.frame_id = BARRIER
        elif pub is self.impulse_pub:
            msg = CgaImpulse(body=BARRIER)
        else:
            msg = CgaWrench(body=BARRIER)
        pub.publish(msg)
        self.wait_rejected(before + 1)

    def wait_rejected(self, count, timeout=TIMEOUT):
        wait_until(lambda: self.rejected == count, timeout,
                   '~rejected_inputs == %d (now %s)' % (count, self.rejected))


def simulator_executable():
    """Path of the built simulator node, for tests that start their own processes."""
    found = roslib.packages.find_node('cga_rigid_sim', 'simulator')
    assert found, 'the simulator executable is not built'
    return found[0]


def start_simulator(name, *args):
    """Starts a simulator process as node `name` with rosrun-style arguments ('_dt:=0.01'),
    against the test's master. Its stdout and stderr both go to proc.stdout (text)."""
    return subprocess.Popen([simulator_executable(), '__name:=' + name] + list(args),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def start_failure(name, *args, timeout=TIMEOUT):
    """Starts a simulator that is expected to refuse its start; returns (exit status, output)
    once it has ended."""
    proc = start_simulator(name, *args)
    out, _ = proc.communicate(timeout=timeout)
    return proc.returncode, out


class Recorder(object):
    """`rosbag record` of some topics into one bag, started and stopped by a test.

    Runs rosbag's recorder executable itself, not the `rosbag` wrapper script: the wrapper runs
    it as a child, so a signal to the wrapper would not wait for the bag to be closed.
    """

    def __init__(self, path, topics, name='record'):
        found = roslib.packages.find_node('rosbag', 'record')
        assert found, "rosbag's record executable not found"
        self.path, self.topics, self.name = path, list(topics), '/' + name
        self.proc = subprocess.Popen([found[0], '-O', path, '__name:=' + name] + self.topics,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
        wait_until(self._subscribed, what='rosbag record subscribed to %s' % self.topics)
        time.sleep(1.0)  # registered with the master; let the publishers connect to it

    def _subscribed(self):
        _, subscribers, _ = rosgraph.Master('/recorder_probe').getSystemState()
        subscribed = {t for t, nodes in subscribers if self.name in nodes}
        return all(t in subscribed for t in self.topics)

    def stop(self):
        """Ctrl-C to the recorder; returns once the bag is closed."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            self.proc.wait(timeout=TIMEOUT)
        wait_for_bag(self.path)


# ---- small vector and quaternion algebra (tuples; quaternions (w, x, y, z)) ----

def vec(m):
    return (m.x, m.y, m.z)


def quat(m):
    return (m.w, m.x, m.y, m.z)


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def scale(k, a):
    return tuple(k * x for x in a)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(sum(x * x for x in a))


def max_abs_diff(a, b):
    return max(abs(x - y) for x, y in zip(a, b))


def quat_mul(p, q):
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return (pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw)


def quat_conj(q):
    return (q[0], -q[1], -q[2], -q[3])


def rotate(q, v):
    return quat_mul(quat_mul(q, (0.0,) + tuple(v)), quat_conj(q))[1:]


def rpy_to_quat(roll, pitch, yaw):
    """URDF fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    def axis(angle, i):
        q = [math.cos(angle / 2), 0.0, 0.0, 0.0]
        q[1 + i] = math.sin(angle / 2)
        return tuple(q)
    return quat_mul(axis(yaw, 2), quat_mul(axis(pitch, 1), axis(roll, 0)))


def quat_distance(p, q):
    """Distance of two unit quaternions up to the double cover (0 for the same rotation)."""
    return min(max_abs_diff(p, q), max_abs_diff(p, scale(-1.0, q)))


def compose(pose_ab, pose_bc):
    """(t, q) poses: frame c in a from c in b and b in a."""
    t_ab, q_ab = pose_ab
    t_bc, q_bc = pose_bc
    return (add(t_ab, rotate(q_ab, t_bc)), quat_mul(q_ab, q_bc))


def state_fields(state):
    """Every number of a BodyState, for bit-for-bit comparisons."""
    p, o = state.pose.position, state.pose.orientation
    t = state.twist
    return ((p.x, p.y, p.z, o.w, o.x, o.y, o.z) + vec(state.com) + vec(t.linear) +
            vec(t.angular) + tuple(state.motor) + tuple(state.bivelocity))


def make_wrench(body, f, point=(0.0, 0.0, 0.0), torque=(0.0, 0.0, 0.0), frame='world',
                stamp=None, duration=0.0, alpha=0.0):
    msg = CgaWrench(body=body, alpha=alpha, duration=duration)
    msg.header.frame_id = frame
    if stamp is not None:
        msg.header.stamp = stamp
    msg.f.x, msg.f.y, msg.f.z = f
    msg.point.x, msg.point.y, msg.point.z = point
    msg.torque.x, msg.torque.y, msg.torque.z = torque
    return msg


def make_impulse(body, f, point=(0.0, 0.0, 0.0), torque=(0.0, 0.0, 0.0), frame='world',
                 stamp=None, alpha=0.0):
    msg = CgaImpulse(body=body, alpha=alpha)
    msg.header.frame_id = frame
    if stamp is not None:
        msg.header.stamp = stamp
    msg.f.x, msg.f.y, msg.f.z = f
    msg.point.x, msg.point.y, msg.point.z = point
    msg.torque.x, msg.torque.y, msg.torque.z = torque
    return msg


def make_plain_wrench(link, force, torque=(0.0, 0.0, 0.0), stamp=None):
    msg = WrenchStamped()
    msg.header.frame_id = link
    if stamp is not None:
        msg.header.stamp = stamp
    msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z = force
    msg.wrench.torque.x, msg.wrench.torque.y, msg.wrench.torque.z = torque
    return msg


def make_trajectory(joint_names, points, stamp=None):
    """trajectory_msgs/JointTrajectory of (time_from_start s, positions, velocities or None)."""
    msg = JointTrajectory(joint_names=list(joint_names))
    if stamp is not None:
        msg.header.stamp = stamp
    for t, positions, velocities in points:
        msg.points.append(JointTrajectoryPoint(positions=list(positions),
                                               velocities=list(velocities or []),
                                               time_from_start=rospy.Duration(t)))
    return msg


def joint_fields(msg):
    """Every number of a sensor_msgs/JointState, for bit-for-bit comparisons."""
    return tuple(msg.position) + tuple(msg.velocity) + tuple(msg.effort)


def body(array_msg, name):
    """The entry `name` of a MomentumArray or BodyStateArray."""
    for b in array_msg.bodies:
        if getattr(b, 'body', None) == name or getattr(b, 'name', None) == name:
            return b
    raise AssertionError('no entry %r in %s' % (name, type(array_msg).__name__))


def wait_for_bag(path, timeout=30.0):
    """Waits until rosbag record has closed the bag at `path`.

    `rosbag record` is a Python wrapper around the C++ recorder: the wrapper can exit on SIGINT
    while its child is still writing the index and renaming `<path>.active` to `<path>`.
    """
    wait_until(lambda: os.path.exists(path) and not os.path.exists(path + '.active'),
               timeout=timeout, what='rosbag record to close ' + path, period=0.05)
