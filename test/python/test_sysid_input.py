"""Bad measured input and bad parameter ranges are refused naming file, row or field and the
rule (doc/fitting.md#input); good input is read as written."""
import os
import shutil

import numpy as np
import pytest

import cga_rigid_sim as cs
from cga_rigid_sim.sysid import model, trajectories
from cga_rigid_sim.sysid.trajectories import TrajectoryError

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, 'data', 'cube_tosses')
HEADER = 'qw,qx,qy,qz,x,y,z,wx,wy,wz,vx,vy,vz'


def write(tmp_path, name, lines):
    p = tmp_path / name
    p.write_text('\n'.join(lines) + '\n')
    return str(p)


def good_rows(n=12, t=False):
    rows = []
    for k in range(n):
        row = '1,0,0,0,%g,0,%g,0,0,0,1,0,0' % (0.01 * k, 0.3 - 0.001 * k)
        rows.append(('%g,' % (k / 100.0) + row) if t else row)
    return rows


def test_the_data_set_is_read_as_written():
    tr = trajectories.read_csv(os.path.join(DATA, '000.csv'))
    assert len(tr) == 121
    assert tr.t[1] == pytest.approx(1 / 148.0)
    assert np.allclose(np.linalg.norm(tr.quaternion, axis=1), 1.0, atol=1e-12)
    first = open(os.path.join(DATA, '000.csv')).read().splitlines()[1].split(',')
    assert tr.position[0, 0] == float(first[4])
    assert len(trajectories.read_directory(DATA)) == 8


@pytest.mark.parametrize('lines, where, rule', [
    (['qw,qx,qy,qz,x,y,z'] + ['1,0,0,0,0,0,0'] * 12, 'header', 'missing wx'),
    ([HEADER.replace('qw', 'w')] + good_rows(), 'header', 'unknown w'),
    ([HEADER] + good_rows(3) + ['1,0,0,0,0,0,nan,0,0,0,1,0,0'] + good_rows(), 'row 4, field z',
     'not finite'),
    ([HEADER] + good_rows(5) + ['1,0,0,0,0,0,inf,0,0,0,1,0,0'] + good_rows(), 'row 6, field z',
     'not finite'),
    ([HEADER] + good_rows(2) + ['1,0,0,0,abc,0,0,0,0,0,1,0,0'] + good_rows(), 'row 3, field x',
     'not a number'),
    ([HEADER] + good_rows(7) + ['0.9,0.1,0,0,0,0,0,0,0,0,1,0,0'] + good_rows(),
     'row 8, fields qw,qx,qy,qz', 'not a unit quaternion'),
    ([HEADER] + good_rows(2) + ['1,0,0,0,0,0,0,0,0,0,1,0'] + good_rows(), 'row 3',
     'has 12 values, the header names 13'),
    ([HEADER] + good_rows(4), 'rows', 'has 4 samples, at least 10 needed'),
    ([], 'header', 'the file is empty'),
])
def test_malformed_csv_is_refused_by_file_row_field_and_rule(tmp_path, lines, where, rule):
    path = write(tmp_path, 'toss.csv', lines)
    with pytest.raises(TrajectoryError) as e:
        trajectories.read_csv(path)
    msg = str(e.value)
    assert msg.startswith(path + ': ' + where + ': '), msg
    assert rule in msg


def test_time_going_backwards_is_refused(tmp_path):
    rows = good_rows(12, t=True)
    rows[6] = '0.01,' + rows[6].split(',', 1)[1]  # t = 0.01 after 0.05
    path = write(tmp_path, 'timed.csv', ['t,' + HEADER] + rows)
    with pytest.raises(TrajectoryError, match=r'row 7, field t: time must increase'):
        trajectories.read_csv(path)
    ok = trajectories.read_csv(write(tmp_path, 'ok.csv', ['t,' + HEADER] + good_rows(12, t=True)))
    assert ok.t[3] == pytest.approx(0.03)


def test_a_bag_without_the_frame_is_refused(tmp_path):
    rosbag = pytest.importorskip('rosbag')
    import rospy
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage
    path = str(tmp_path / 'tf.bag')
    with rosbag.Bag(path, 'w') as bag:
        for k in range(20):
            tr = TransformStamped()
            tr.header.frame_id = 'world'
            tr.header.stamp = rospy.Time.from_sec(1.0 + k / 100.0)
            tr.child_frame_id = 'other'
            tr.transform.rotation.w = 1.0
            tr.transform.translation.z = 0.3 - 0.01 * k
            bag.write('/tf', TFMessage(transforms=[tr]), tr.header.stamp)
    with pytest.raises(TrajectoryError, match=r"tf\.bag: frame 'body': no transform world -> body"
                                              r" on /tf \(frames in the bag: other\)"):
        trajectories.read_bag(path, 'body')
    runs = trajectories.read_bag(path, 'other')
    assert len(runs) == 1 and len(runs[0]) == 20
    assert runs[0].position[5, 2] == pytest.approx(0.25)
    assert runs[0].t[5] == pytest.approx(0.05)


def test_a_urdf_without_a_collision_shape_is_refused():
    scene = cs.load_urdf('<robot name="r"><link name="a"><inertial><mass value="1"/>'
                         '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>'
                         '</inertial></link></robot>')
    with pytest.raises(model.ParameterError, match="body 'a' has no <collision> shape"):
        model.object_size(scene, 'a')
    size, radius = model.object_size(cs.load_urdf(os.path.join(DATA, 'cube.urdf')), 'body')
    assert size == 0.1048 and radius == pytest.approx(0.0524 * np.sqrt(3))


@pytest.mark.parametrize('text, rule', [
    ('', 'the range is empty'),
    ('mu=0.6:0.1', 'mu: empty range 0.6:0.1'),
    ('mu=-0.1:0.5', 'mu: -0.1 is not physical'),
    ('restitution=0:1.5', 'restitution: 1.5 is not physical'),
    ('static_friction_ratio=0.5:2', 'static_friction_ratio: 0.5 is not physical'),
    ('stribeck_speed=0:0.1', 'stribeck_speed: 0 is not physical'),
    ('height=nan:0', 'height: must be a finite number'),
    ('friction=0:1', 'friction: unknown parameter'),
    ('mu=0.1:0.2,mu=0.3', 'mu: given twice'),
    ('mu', 'expected name=low:high'),
])
def test_empty_or_unphysical_ranges_are_refused(text, rule):
    with pytest.raises(model.ParameterError) as e:
        model.parse_ranges(text)
    assert rule in str(e.value)


def test_ranges_are_read():
    r = model.parse_ranges('mu=0.05:0.6, restitution=0.1, height=-0.004:0.002')
    assert r == {'mu': (0.05, 0.6), 'restitution': (0.1, 0.1), 'height': (-0.004, 0.002)}


def test_the_command_refuses_bad_input_with_status_2(tmp_path, capsys):
    from cga_rigid_sim.sysid import cli
    d = tmp_path / 'data'
    d.mkdir()
    shutil.copy(os.path.join(DATA, '000.csv'), d / '000.csv')
    (d / '001.csv').write_text(HEADER + '\n' + '\n'.join(good_rows(5)) + '\n')
    rc = cli.main(['eval', str(d), '--urdf', os.path.join(DATA, 'cube.urdf'),
                   '--set', 'mu=0.2', '--no-dask'])
    assert rc == 2
    err = capsys.readouterr().err
    assert '001.csv: rows: has 5 samples' in err
    rc = cli.main(['eval', os.path.join(DATA, '000.csv'), '--urdf',
                   os.path.join(DATA, 'cube.urdf'), '--set', 'mu=-1', '--no-dask'])
    assert rc == 2 and 'mu: -1 is not physical' in capsys.readouterr().err


def test_a_start_outside_the_ranges_or_missing_a_parameter_is_refused(capsys):
    from cga_rigid_sim.sysid import cli
    common = ['cv', os.path.join(DATA, '000.csv'), '--urdf', os.path.join(DATA, 'cube.urdf'),
              '--model', 'a:mu=0.1:0.3,height=-0.003:0', '--no-dask']
    for start, rule in (('mu=0.5,height=0', 'mu=0.5 is outside its range 0.1:0.3'),
                        ('mu=0.2', 'height is not given'),
                        ('mu', "--start 'mu': expected NAME=VALUE")):
        assert cli.main(common + ['--start', start]) == 2
        assert rule in capsys.readouterr().err
