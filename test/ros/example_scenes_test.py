#!/usr/bin/env python3
"""Every example scene starts with its initial state, as its launch file starts it.

Truth: the files themselves. For each config/<scene>.yaml the node is started on
urdf/<scene>.urdf with that file's `initial_state` (what launch/<scene>.launch loads): it must
come up (its ~step service answers) and not refuse its start, so a name in a config that the
URDF does not have, a joint key of a body, or a position outside the limits (a warning) is
caught here rather than by a user's first roslaunch. A scene with joints must also advertise
/joint_states with every joint its config names. A scene with config/<scene>_controllers.yaml
(ros_control controllers) is started with them too, loaded into the node's namespace and run
by the names its launch file's `controller_names` gives: its controllers must start without a
warning either.
"""
import glob
import os
import signal
import sys
import unittest
import xml.etree.ElementTree as ElementTree

import rosgraph
import rospkg
import rospy
import rostest
import yaml
from cga_rigid_sim.srv import Step
from sensor_msgs.msg import JointState

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from sim_test_util import start_simulator, wait_until  # noqa: E402

PACKAGE = rospkg.RosPack().get_path('cga_rigid_sim')


CONTROLLERS_SUFFIX = '_controllers'


def controllers_of(scene):
    """(controllers YAML dictionary, names its launch file runs) of a scene, or None."""
    path = os.path.join(PACKAGE, 'config', scene + CONTROLLERS_SUFFIX + '.yaml')
    if not os.path.exists(path):
        return None
    with open(path) as f:
        controllers = yaml.safe_load(f)
    launch = ElementTree.parse(os.path.join(PACKAGE, 'launch', scene + '.launch'))
    names = [a.get('default') for a in launch.getroot().iter('arg')
             if a.get('name') == 'controller_names']
    assert names, 'launch/%s.launch has no controller_names argument' % scene
    return controllers, names[0]


def example_scenes():
    """(scene, urdf path, initial_state dictionary, controllers_of(scene)) for every
    config/<scene>.yaml (not the controllers' files, config/<scene>_controllers.yaml)."""
    out = []
    for config in sorted(glob.glob(os.path.join(PACKAGE, 'config', '*.yaml'))):
        scene = os.path.splitext(os.path.basename(config))[0]
        if scene.endswith(CONTROLLERS_SUFFIX):
            continue
        with open(config) as f:
            initial_state = yaml.safe_load(f)['initial_state']
        out.append((scene, os.path.join(PACKAGE, 'urdf', scene + '.urdf'), initial_state,
                    controllers_of(scene)))
    return out


class ExampleScenesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('example_scenes_test')

    def test_the_examples_are_there(self):
        scenes = [s for s, _, _, _ in example_scenes()]
        for expected in ['tennis_racket', 'symmetric_top', 'thin_rod', 'dumbbell', 'projectile',
                         't_handle', 'many_bodies', 'tabletop', 'double_pendulum', 'arm7',
                         'satellite', 'rover']:
            self.assertIn(expected, scenes)
        for scene in scenes:
            self.assertTrue(os.path.exists(os.path.join(PACKAGE, 'launch', scene + '.launch')),
                            scene + ' has no launch file')
        self.assertIsNotNone(controllers_of('arm7'))

    def test_every_example_scene_starts_with_its_initial_state(self):
        master = rosgraph.Master('/example_scenes_test')
        joint_states = []
        sub = rospy.Subscriber('/joint_states', JointState, joint_states.append, queue_size=None)
        for scene, urdf, initial_state, controllers in example_scenes():
            name = 'example_' + scene
            rospy.set_param('/%s/initial_state' % name, initial_state)
            args = ['_urdf_file:=' + urdf, '_paused:=true', '_publish_clock:=false']
            if controllers:  # in the node's namespace, /, as the launch file loads them
                for key, value in controllers[0].items():
                    rospy.set_param('/' + key, value)
                args.append('_controllers:=' + controllers[1])
            proc = start_simulator(name, *args)
            try:
                wait_until(lambda: proc.poll() is not None or
                           any(s == '/%s/step' % name for s, _ in master.getSystemState()[2]),
                           what=name + ' up')
                if proc.poll() is not None:
                    self.fail('%s did not start:\n%s' % (scene, proc.communicate()[0]))
                # Joint entries hold numbers, body entries lists.
                joints = [k for k, v in initial_state.items()
                          if any(isinstance(x, (int, float)) for x in v.values())]
                if joints:
                    wait_until(lambda: sub.get_num_connections() > 0,
                               what=name + "'s /joint_states connected")
                    del joint_states[:]
                # 20 steps: one period of the controller scenes' 50 Hz joint_state_controller at
                # dt = 1 ms, so a /joint_states tick falls within them (10 held none, and the
                # test then hung on whether the start's message beat the list's clearing).
                rospy.ServiceProxy('/%s/step' % name, Step)(20)
                if joints:
                    wait_until(lambda: joint_states, what=name + "'s /joint_states")
                    self.assertLessEqual(set(joints), set(joint_states[-1].name), scene)
            finally:
                out = ''
                if proc.poll() is None:
                    proc.send_signal(signal.SIGINT)
                    out, _ = proc.communicate(timeout=10.0)
                rospy.delete_param('/' + name)
                for key in (controllers[0] if controllers else {}):
                    rospy.delete_param('/' + key)
            self.assertNotIn('FATAL', out, '%s did not start:\n%s' % (scene, out))
            self.assertNotIn('WARN', out, '%s warned at start:\n%s' % (scene, out))
        sub.unregister()


if __name__ == '__main__':
    rostest.rosrun('cga_rigid_sim', 'example_scenes', ExampleScenesTest)
