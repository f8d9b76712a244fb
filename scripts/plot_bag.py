#!/usr/bin/python3
"""Plot energy, angular momentum and momentum of a recorded run, and their relative drift.

    scripts/plot_bag.py <bag> <out.png> [--body NAME] [--topic TOPIC] [--title TEXT]

Reads the simulator's momentum topic (cga_rigid_sim/MomentumArray, default
/simulator/momentum) from a bag recorded with `roslaunch cga_rigid_sim record.launch` and draws,
against the simulation time of each message's stamp:
  1. energy: kinetic, potential, dissipated by contacts, and their sum E (J);
  2. |L| (angular momentum about the centre of mass, kg m^2/s) and |P| (linear momentum, kg m/s);
  3. the drift of each from its first value: (E - E0)/|E0|, (|L| - |L0|)/|L0|, |P - P0|/|P0|;
     a quantity whose first value is 0 is drawn as its absolute change instead (the legend says
     which);
  4. when the bag has the body states (/simulator/body_states, recorded by record.launch): the
     body's angular velocity in its own principal axes (the bivelocity's e23, e31, e12
     coefficients), where a tennis racket's flips show. With `total` this is the scene's only
     moving body, and the panel is left out for a scene of several.
By default the scene's `total` entry (the sum over moving bodies; L about the system's centre
of mass); --body plots one body instead. Inputs (wrenches, impulses, joint efforts) do work: the
drift panel then shows that work, not an integration error.
Needs python3-matplotlib and the ROS python packages (rosbag); not the workspace (messages are
read from the definitions stored in the bag). Exit status 1 with a message if the bag or the
topic or body is missing.
"""
import argparse
import math
import sys


def fail(text):
    print('plot_bag.py: ' + text, file=sys.stderr)
    sys.exit(1)


def read_series(bag_path, topic, body):
    import rosbag  # Debian python3-rosbag / ros-noetic-rosbag
    try:
        bag = rosbag.Bag(bag_path)
    except Exception as e:  # rosbag raises several types (ROSBagException, IOError, ...)
        fail('cannot open bag %s: %s' % (bag_path, e))
    with bag:
        topics = bag.get_type_and_topic_info().topics
        if topic not in topics:
            fail('bag %s has no topic %s (topics: %s)' % (bag_path, topic, ', '.join(sorted(topics))))
        rows = []
        names = set()
        for _, msg, _ in bag.read_messages(topics=[topic]):
            for m in msg.bodies:
                names.add(m.body)
                if m.body == body:
                    rows.append((msg.header.stamp.to_sec(), m))
    if not rows:
        fail('topic %s has no entry for body %r (bodies: %s)' % (topic, body, ', '.join(sorted(names))))
    rows.sort(key=lambda r: r[0])
    return rows


def read_body_rates(bag_path, topic, body):
    """[(t, (w1, w2, w3))] of `body` (body axes), or [] when the topic or body is absent."""
    import rosbag
    rows = []
    with rosbag.Bag(bag_path) as bag:
        if topic not in bag.get_type_and_topic_info().topics:
            return []
        for _, msg, _ in bag.read_messages(topics=[topic]):
            states = msg.bodies
            if body == 'total':
                if len(states) != 1:
                    return []
                states = list(states)
            for s in states:
                if body == 'total' or s.name == body:
                    rows.append((msg.header.stamp.to_sec(), tuple(s.bivelocity[0:3])))
    rows.sort(key=lambda r: r[0])
    return rows


def norm(v):
    return math.sqrt(v.x * v.x + v.y * v.y + v.z * v.z)


def drift(values, first, vector=False):
    """(v - v0)/|v0|, or v - v0 when v0 == 0; `vector` values are 3-tuples (|v - v0|)."""
    if vector:
        scale = math.sqrt(sum(c * c for c in first))
        change = [math.sqrt(sum((a - b) ** 2 for a, b in zip(v, first))) for v in values]
    else:
        scale = abs(first)
        change = [v - first for v in values]
    if scale > 0.0:
        return [c / scale for c in change], True
    return change, False


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('bag')
    parser.add_argument('out', help='PNG file to write')
    parser.add_argument('--body', default='total', help='a body name, or total (default)')
    parser.add_argument('--topic', default='/simulator/momentum')
    parser.add_argument('--states-topic', default='/simulator/body_states')
    parser.add_argument('--title', default=None)
    args = parser.parse_args()

    rows = read_series(args.bag, args.topic, args.body)
    t = [r[0] for r in rows]
    ke = [r[1].kinetic_energy for r in rows]
    pe = [r[1].potential_energy for r in rows]
    de = [r[1].dissipated_energy for r in rows]
    e = [a + b + c for a, b, c in zip(ke, pe, de)]
    L = [norm(r[1].angular) for r in rows]
    P_vec = [(r[1].linear.x, r[1].linear.y, r[1].linear.z) for r in rows]
    P = [math.sqrt(sum(c * c for c in p)) for p in P_vec]

    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    rates = read_body_rates(args.bag, args.states_topic, args.body)
    panels = 4 if rates else 3
    fig, axes = plt.subplots(panels, 1, figsize=(7.5, 2.4 * panels + 0.6), sharex=True)
    ax = axes[0]
    energy_lines = [ke, e]
    ax.plot(t, ke, label='kinetic')
    if any(pe):
        ax.plot(t, pe, label='potential')
        energy_lines.append(pe)
    if any(de):
        ax.plot(t, de, label='dissipated')
        energy_lines.append(de)
    ax.plot(t, e, 'k--', label='E = sum')
    ax.set_ylabel('energy (J)')
    ax.ticklabel_format(axis='y', useOffset=False)
    ax.legend(loc='best', fontsize='small')
    ax.grid(alpha=0.3)

    ax = axes[1]
    ax.plot(t, L, color='tab:orange', label='|L| (about CoM)')
    ax.set_ylabel('|L| (kg m²/s)', color='tab:orange')
    ax.grid(alpha=0.3)
    ax2 = ax.twinx()
    ax2.plot(t, P, color='tab:blue', linestyle='--', label='|P|')
    ax2.set_ylabel('|P| (kg m/s)', color='tab:blue')
    # A constant quantity would get an axis spanning round-off: show a range around it.
    for a, vals in ((axes[0], sum(energy_lines, [])), (ax, L), (ax2, P)):
        lo, hi = min(vals), max(vals)
        if hi - lo <= 1e-9 * max(abs(hi), 1e-300):
            pad = max(abs(hi) * 0.1, 1e-3)
            a.set_ylim(lo - pad, hi + pad)

    ax = axes[2]
    for name, values, vector in (('E − E0', e, False), ('|L| − |L0|', L, False),
                                 ('|P − P0|', P_vec, True)):
        d, relative = drift(values, values[0], vector)
        ax.plot(t, d, label=name + (' (relative)' if relative else ' (absolute)'))
    ax.set_ylabel('drift')
    ax.set_xlabel('simulation time (s)')
    ax.ticklabel_format(axis='y', style='sci', scilimits=(-3, 3))
    ax.legend(loc='best', fontsize='small')
    ax.grid(alpha=0.3)

    if rates:
        ax = axes[3]
        tr = [r[0] for r in rates]
        for k, axis in enumerate(('1', '2', '3')):
            ax.plot(tr, [r[1][k] for r in rates], label='ω' + axis)
        ax.set_ylabel('ω, body axes (rad/s)')
        ax.legend(loc='best', fontsize='small', ncol=3)
        ax.grid(alpha=0.3)
        axes[2].set_xlabel('')
        ax.set_xlabel('simulation time (s)')

    title = args.title or '%s: %s, %d samples, t = %.3g–%.3g s' % (
        args.bag.split('/')[-1], args.body, len(t), t[0], t[-1])
    fig.suptitle(title, fontsize='medium')
    fig.tight_layout()
    fig.savefig(args.out, dpi=90)
    print('plot_bag.py: wrote %s (%d samples of %s, t = %g to %g s)' % (args.out, len(t), args.body,
                                                                        t[0], t[-1]))


if __name__ == '__main__':
    main()
