#!/usr/bin/python3
"""rviz loads the package's configuration (rviz/cga_rigid_sim.rviz) on a scene without errors.

test/ros/rviz.test launches the tabletop scene (launch/tabletop.launch: a static table of five
merged links, three free bodies, contacts on the ground plane). This node starts a private X
server (Xvfb; the current DISPLAY only if there is no Xvfb) and rviz on it with the shipped
configuration, as `rviz:=true` does, and checks:
  - rviz's displays are live: the /rviz node subscribes to /tf, /tf_static and the node's
    /simulator/markers, and a MarkerArray with the bodies' arrows reaches it;
  - every link of robot_description has a transform to `world` from the node's tf (what the
    RobotModel needs: a link without one is drawn in rviz's error material or not at all);
  - the RobotModel draws the scene: the URDF's visuals carry no material, which rviz draws in
    lit red, while a link without its transform is hidden or drawn in unlit white; a screenshot
    of the view holds thousands of red pixels with the RobotModel, and the same view with the
    RobotModel display turned off (the control: grid, tf axes and markers only) a few;
  - rviz says nothing at WARN or above on /rosout and prints no ERROR/WARN line. (Debian's rviz
    prints "[rospack] Error: no such package media_export" at start: it looks for that
    package's plugin path, which Debian does not ship; not an rviz log line, not counted.)
Skipped, with the reason printed, only when no X server can run (neither Xvfb nor a DISPLAY).
"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import rosgraph
import rospy
import rostest
import tf2_ros
import yaml
from rosgraph_msgs.msg import Log

PKG = 'cga_rigid_sim'
TIMEOUT = 45.0  # s of wall time for rviz to come up under software GL on a loaded machine


def package_dir():
    return os.path.abspath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))


def start_xvfb(width, height):
    """(process, display) of a private Xvfb, or (None, reason)."""
    xvfb = shutil.which('Xvfb')
    if not xvfb:
        return None, 'Xvfb not found (install xvfb)'
    read_fd, write_fd = os.pipe()
    proc = subprocess.Popen(
        [xvfb, '-displayfd', str(write_fd), '-screen', '0', '%dx%dx24' % (width, height),
         '-nolisten', 'tcp'], pass_fds=(write_fd,), stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL)
    os.close(write_fd)
    number = b''
    deadline = time.time() + 15.0
    with os.fdopen(read_fd, 'rb') as f:
        while time.time() < deadline and not number.endswith(b'\n'):
            chunk = f.read(1)
            if not chunk:
                break
            number += chunk
    if not number.strip():
        proc.kill()
        return None, 'Xvfb did not start'
    return proc, ':' + number.decode().strip()


class RvizTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('rviz_test')
        cls.rosout = []
        rospy.Subscriber('/rosout', Log, lambda m: cls.rosout.append(m), queue_size=1000)
        cls.markers = []
        cls.xvfb = None
        cls.rviz = None
        cls.skip_reason = None
        cls.work = tempfile.mkdtemp(prefix='rviz_test.')
        cls.width, cls.height = 1024, 768
        cls.xvfb, display = start_xvfb(cls.width, cls.height)
        if cls.xvfb is None:
            if os.environ.get('DISPLAY'):
                print('rviz_test: %s; using DISPLAY=%s' % (display, os.environ['DISPLAY']))
                display = os.environ['DISPLAY']
            else:
                cls.skip_reason = 'no X server can run here: %s and DISPLAY is unset' % display
                print('rviz_test: SKIPPED: ' + cls.skip_reason)
                return
        cls.display = display

    @classmethod
    def tearDownClass(cls):
        cls.stop_rviz()
        if cls.xvfb is not None:
            cls.xvfb.terminate()
            cls.xvfb.wait(10)
        shutil.rmtree(cls.work, ignore_errors=True)

    @classmethod
    def start_rviz(cls, config, log_name):
        env = dict(os.environ, DISPLAY=cls.display)
        cls.rviz_log = os.path.join(cls.work, log_name)
        cls.rviz = subprocess.Popen(['rosrun', 'rviz', 'rviz', '-d', config, '__name:=rviz'],
                                    env=env, stdout=open(cls.rviz_log, 'w'),
                                    stderr=subprocess.STDOUT, start_new_session=True)

    @classmethod
    def stop_rviz(cls):
        if cls.rviz is None:
            return
        os.killpg(cls.rviz.pid, signal.SIGINT)
        try:
            cls.rviz.wait(15)
        except subprocess.TimeoutExpired:
            os.killpg(cls.rviz.pid, signal.SIGKILL)
            cls.rviz.wait()
        cls.rviz = None

    def wait_for_subscriptions(self, topics):
        master = rosgraph.Master('/rviz_test')
        deadline = time.time() + TIMEOUT
        missing = topics
        while time.time() < deadline:
            self.assertIsNone(self.rviz.poll(), 'rviz exited:\n' + open(self.rviz_log).read())
            _, subscribers, _ = master.getSystemState()
            subscribed = {t for t, nodes in subscribers if '/rviz' in nodes}
            missing = [t for t in topics if t not in subscribed]
            if not missing:
                return
            time.sleep(0.5)
        self.fail('rviz did not subscribe to %s within %g s; its output:\n%s'
                  % (missing, TIMEOUT, open(self.rviz_log).read()))

    def screenshot(self, name):
        """The screen as an RGB PIL image (ImageMagick's import)."""
        from PIL import Image  # python3-pil (a dependency of python3-matplotlib)
        path = os.path.join(self.work, name)
        subprocess.run(['import', '-display', self.display, '-window', 'root', path], check=True,
                       timeout=30)
        return Image.open(path).convert('RGB')

    def view_config(self, robot_model):
        """The shipped configuration, side panels hidden, RobotModel on or off, window = screen."""
        with open(os.path.join(package_dir(), 'rviz', 'cga_rigid_sim.rviz')) as f:
            config = yaml.safe_load(f)
        for d in config['Visualization Manager']['Displays']:
            if d['Class'] == 'rviz/RobotModel':
                d['Enabled'] = robot_model
        config['Panels'] = []
        config['Window Geometry'] = {'Width': self.width, 'Height': self.height, 'X': 0, 'Y': 0,
                                     'Hide Left Dock': True, 'Hide Right Dock': True}
        path = os.path.join(self.work, 'robot_model_%s.rviz' % robot_model)
        with open(path, 'w') as f:
            yaml.safe_dump(config, f)
        return path

    @staticmethod
    def count_pixels(image):
        """(red, grid): pixels of rviz's lit red default material (red dominant: green and blue
        under a quarter of it), and of the grid (grey 160 at alpha 0.5 over the background 48,
        about 104, channels within 6)."""
        red = grid = 0
        for r, g, b in image.getdata():
            if r >= 80 and 4 * g <= r and 4 * b <= r:
                red += 1
            elif 90 <= r <= 120 and abs(r - g) <= 6 and abs(r - b) <= 6:
                grid += 1
        return red, grid

    def test_rviz_loads_the_config(self):
        if self.skip_reason:
            self.skipTest(self.skip_reason)

        # Every link of the scene has a transform to world from the node (RobotModel's needs).
        links = self.urdf_links()
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        deadline = time.time() + 20.0
        missing = links
        while time.time() < deadline and missing:
            missing = [l for l in links if not buffer.can_transform('world', l, rospy.Time(0))]
            time.sleep(0.2)
        self.assertEqual(missing, [], 'links without a transform to world')

        # The shipped configuration as it is: displays live, markers flowing, nothing said.
        from visualization_msgs.msg import MarkerArray
        rospy.Subscriber('/simulator/markers', MarkerArray, lambda m: self.markers.append(m))
        self.start_rviz(os.path.join(package_dir(), 'rviz', 'cga_rigid_sim.rviz'), 'rviz.log')
        self.wait_for_subscriptions(['/tf', '/tf_static', '/simulator/markers'])
        deadline = time.time() + 10.0
        while time.time() < deadline and not self.markers:
            time.sleep(0.1)
        self.assertTrue(self.markers, 'no MarkerArray on /simulator/markers')
        # The bodies rest on the table and the floor: their contacts are drawn.
        namespaces = {m.ns for m in self.markers[-1].markers}
        self.assertIn('contacts', namespaces)
        time.sleep(3.0)  # rviz draws a few frames, and would say what it dislikes
        self.stop_rviz()
        self.assert_rviz_quiet()

        # The RobotModel draws the scene: red pixels with it, few without it.
        with_model = self.render(robot_model=True)
        without_model = self.render(robot_model=False)
        print('rviz_test: red pixels with the RobotModel %d, without %d'
              % (with_model, without_model))
        # Measured on this 1024x768 view: 34 640 red pixels for the scene, 97 in the control (the
        # tf axes' red x arrows); with the RobotModel pointed at a missing parameter (no links
        # drawn) 97 and 97, and this test fails. 5000 and a tenth leave a wide margin either way.
        self.assertGreater(with_model, 5000)
        self.assertLess(without_model, with_model / 10)

    def render(self, robot_model):
        """Red pixels of the view, once rviz has drawn it: the grid is on screen (rviz renders)
        and the red count has settled (within 2 %, or 50 pixels, between two screenshots a second
        apart: the RobotModel has its transforms; a rolling ball changes a few pixels)."""
        self.start_rviz(self.view_config(robot_model), 'rviz_model_%s.log' % robot_model)
        self.wait_for_subscriptions(['/tf', '/simulator/markers'])
        deadline = time.time() + TIMEOUT
        previous = None
        while True:
            red, grid = self.count_pixels(self.screenshot('model_%s.png' % robot_model))
            if grid > 1000 and previous is not None and abs(red - previous) <= max(50, red // 50):
                break
            self.assertLess(time.time(), deadline,
                            'rviz drew no steady view within %g s (red %d, grid %d)'
                            % (TIMEOUT, red, grid))
            previous = red if grid > 1000 else None
            time.sleep(1.0)
        self.stop_rviz()
        return red

    def urdf_links(self):
        import xml.etree.ElementTree as ET
        root = ET.fromstring(rospy.get_param('/robot_description'))
        return [l.get('name') for l in root.findall('link') if l.get('name') != 'world']

    def assert_rviz_quiet(self):
        said = [m for m in self.rosout if m.name == '/rviz' and m.level >= Log.WARN]
        self.assertEqual(['%d %s' % (m.level, m.msg) for m in said], [],
                         'rviz warned or erred on /rosout')
        lines = [l for l in open(self.rviz_log).read().splitlines()
                 if '[ERROR]' in l or '[ WARN]' in l or '[FATAL]' in l]
        self.assertEqual(lines, [], 'rviz printed errors or warnings')


if __name__ == '__main__':
    rostest.rosrun(PKG, 'rviz', RvizTest, sys.argv)
