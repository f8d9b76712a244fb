#!/usr/bin/python3
"""Pick up the box of the pick_place scene and put it down, through the controllers' topics.

    roslaunch cga_rigid_sim pick_place.launch            (starts this script)
    rosrun cga_rigid_sim pick_place.py _hold:=1.0 _loops:=1

The arm follows trajectory_msgs/JointTrajectory on /arm_controller/command, stamped in
simulation time (/use_sim_time, the simulator's /clock) with the time each one starts, so the
sequence's timing does not depend on when the messages arrive; the gripper takes
std_msgs/Float64MultiArray on /gripper_controller/command (finger_left's position; finger_right
mimics it), sent at its time. Parameters: ~hold (s, 1.0) the box is held up before it is carried
over; ~loops (1) how many times it is carried, back and forth, 0 = forever.

The joint targets were computed offline from the arm's kinematics (urdf/pick_place.urdf; the
same numbers drive test/sim/controllers/pick_place_test.cc): the tool points straight down,
joint3 = joint5 = 0 so joints 2, 4 and 6 bend in one vertical plane turned by joint1, the
shoulder (joint2) 1.10 m above the floor, the elbow 0.56 m and the wrist (joint6) 0.48 m further,
the TCP (the point between the fingers where a grasped box's centre sits) 0.235 m from joint6;
a two-link inverse kinematics in that plane (elbow up) gives joints 2 and 4, joint6 = π − (the
forearm's angle) points the tool down, and joint7 = joint1 turns the hand back so that the box
keeps its yaw. Checked by the forward kinematics to 4 µm.
"""
import rospy
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

JOINTS = ['joint1', 'joint2', 'joint3', 'joint4', 'joint5', 'joint6', 'joint7']

# TCP (x, y, z) in the world, m; the box stands on the table with its centre at z = 0.775.
HOME = [0.0, 0.5, 0.0, -1.7, 0.0, 0.95, 0.0]  # the initial state: TCP (0.655, 0, 1.074)
ABOVE_A = [0.00000, 0.86354, 0.00000, -1.53619, 0.00000, 0.74186, 0.00000]  # (0.75, 0, 0.875)
AT_A = [0.00000, 1.00265, 0.00000, -1.52130, 0.00000, 0.61764, 0.00000]     # (0.75, 0, 0.775)
LIFT_A = [0.00000, 0.79982, 0.00000, -1.52968, 0.00000, 0.81210, 0.00000]   # (0.75, 0, 0.925)
# the place, where the box is put down: the same heights at (0.5, 0.55)
LIFT_B = [0.83298, 0.79118, 0.00000, -1.54829, 0.00000, 0.80213, 0.83298]   # z 0.925
AT_B = [0.83298, 0.99578, 0.00000, -1.53991, 0.00000, 0.60590, 0.83298]     # z 0.775
ABOVE_B = LIFT_B

OPEN, CLOSED = [0.0], [0.03]  # finger_left, m: the box's faces are met at 0.02


def carry(frm, to, hold):
    """(t, arm points [(positions, time_from_start)] or gripper command) from `frm` to `to`,
    each a (above, at, lift) triple; the arm starts above `frm`'s box within 2 s."""
    above_f, at_f, lift_f = frm
    above_t, at_t, lift_t = to
    t_carry = 5.0 + hold
    return [
        (0.0, [(above_f, 2.0), (at_f, 3.0)]),  # over the box, then down around it
        (3.2, CLOSED),                         # close on it (0.2 s to meet it at 0.1 m/s)
        (4.0, [(lift_f, 1.0)]),                # lift it 15 cm
        (t_carry, [(lift_t, 2.0), (at_t, 3.0)]),  # carry it over, lower it onto the table
        (t_carry + 3.2, OPEN),                 # let go
        (t_carry + 3.8, [(above_t, 1.0)]),     # up and away
    ], t_carry + 5.0


def trajectory(start, points):
    msg = JointTrajectory()
    msg.header.stamp = start  # simulation time the trajectory starts at
    msg.joint_names = JOINTS
    for positions, t in points:
        msg.points.append(JointTrajectoryPoint(positions=positions, velocities=[0.0] * 7,
                                               time_from_start=rospy.Duration(t)))
    return msg


def main():
    rospy.init_node('pick_place')
    hold = rospy.get_param('~hold', 1.0)
    loops = rospy.get_param('~loops', 1)
    arm = rospy.Publisher('/arm_controller/command', JointTrajectory, queue_size=10)
    gripper = rospy.Publisher('/gripper_controller/command', Float64MultiArray, queue_size=10)
    while not rospy.is_shutdown() and rospy.Time.now().is_zero():  # wait for /clock
        rospy.sleep(0.05)
    while not rospy.is_shutdown() and (arm.get_num_connections() == 0
                                       or gripper.get_num_connections() == 0):
        rospy.sleep(0.1)
    places = [(ABOVE_A, AT_A, LIFT_A), (ABOVE_B, AT_B, LIFT_B)]
    n = 0
    while not rospy.is_shutdown() and (loops == 0 or n < loops):
        frm, to = places[n % 2], places[(n + 1) % 2]
        commands, duration = carry(frm, to, hold)
        t0 = rospy.Time.now() + rospy.Duration(0.5)
        for t, command in commands:
            start = t0 + rospy.Duration(t)
            if command in (OPEN, CLOSED):
                rospy.sleep(start - rospy.Time.now())  # a group command acts when it arrives
                gripper.publish(Float64MultiArray(data=command))
                rospy.loginfo('%.2f s: gripper %s', start.to_sec(),
                              'closes' if command == CLOSED else 'opens')
            else:
                # sent ahead of its start, stamped with it: it replaces the running one then
                rospy.sleep(start - rospy.Duration(0.3) - rospy.Time.now())
                arm.publish(trajectory(start, command))
        rospy.sleep(t0 + rospy.Duration(duration) - rospy.Time.now())
        rospy.loginfo('box carried %s', 'there' if n % 2 == 0 else 'back')
        n += 1


if __name__ == '__main__':
    try:
        main()
    except rospy.ROSInterruptException:
        pass
