#!/usr/bin/python3
"""Node throughput: steps per second of the ROS node `simulator` on many free bodies.

    /usr/bin/python3 bench/node_throughput.py [--ns 1,100,1000,10000] [--rtfs 0,1]
        [--extra 10000:cga2] [--window 8] [--warmup 2] [--node PATH] [--counter PATH]
        [--out bench/out] [--atlas [--ground-shift DZ]]

For every N and every ~real_time_factor (0 = as fast as possible, 1 = real time) the script
starts the node on the scene of `scripts/generate_many_bodies.py N` (with its --initial-state
spins; if the script is missing, an equivalent scene is generated here) with dt = 1 ms,
integrator auto (plus the --extra runs, by default N = 10000 with cga2), ~threads at its
default (the cores available), tf, ~momentum, ~body_states and /clock published at 100 Hz of
simulated time, and a subscriber attached to /tf, ~momentum and ~body_states. That subscriber
is bench_topic_counter (bench/topic_counter.cc, built with the benchmarks), which counts the
messages and bytes without deserialising them, so the benchmark measures the node rather than
its receiver; when it is not built, a rospy subscriber of raw messages stands in (it takes
about half a core at N = 10 000, which the node then lacks). The node still serialises and
sends every message; a subscriber drops what it cannot keep up with, so the received rates can
be lower than the published ones. After the first /clock message and a warm-up, the script
watches /clock for a window of wall time: the simulated time gained over the wall time between
the first and last /clock message received in the window is the achieved real-time factor;
divided by dt, the steps per second. Results go to bench/out/node_throughput.csv (with the
node's thread count, as it logs it, and which subscriber counted).

With --atlas the scene is instead Atlas v3 without head from Debian's dart-doc
(/usr/share/doc/dart/data/sdf/atlas/atlas_v3_no_head.urdf: 28 moving bodies, 27 joints, STL
collision meshes; skipped with a message when dart-doc is absent) with ~ground_plane 1 cm below
its soles and ~self_collision auto, falling and then lying on the plane (the real-robot case of
the contact benchmark, bench/peers/robot_cases.h); n_bodies is 28 and the results go to
bench/out/node_throughput_atlas.csv. Its window starts at the first /clock (--warmup 0 unless
given), so that it holds the fall. Where the robot lands, and whether it comes to rest and
sleeps within the window, depends chaotically on round-off: --ground-shift DZ lowers the plane
by DZ metres, another start of the same case (as bench_contacts --robots --starts does).

Everything runs against a private roscore on a free port (ROS_HOME in a temporary directory), so
other ROS work on the machine is not disturbed. Every process started here (roscore and its
children, each node) is started in its own process group and ended on exit, also on errors and
on SIGINT/SIGTERM. When the node is not built, or rospy is missing, the script writes a CSV whose
rows say why, prints a clear message and exits 0 (a benchmark never fails the build).
"""

import argparse
import atexit
import csv
import math
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_NODE = os.path.join(ROOT, "build", "ws", "devel", "lib", "cga_rigid_sim", "simulator")
DEFAULT_COUNTER = os.path.join(ROOT, "build", "ws", "devel", "lib", "cga_rigid_sim",
                               "bench_topic_counter")
COLUMNS = ["n_bodies", "real_time_factor", "publish_rate_hz", "integrator", "dt", "threads",
           "window_s", "sim_s", "steps_per_s", "achieved_rtf", "ns_per_body_step",
           "tf_received_per_s", "tf_received_mb_per_s", "momentum_received_per_s",
           "body_states_received_per_s", "body_states_received_mb_per_s", "subscriber", "status"]
# --atlas: the URDF, its moving bodies, the plane 1 cm below its lowest point (robot_cases.h).
ATLAS_URDF = "/usr/share/doc/dart/data/sdf/atlas/atlas_v3_no_head.urdf"
ATLAS_BODIES = 28
ATLAS_GROUND_Z = -0.927351 - 0.01
# The counted topics, in the order of the counts (node name "simulator").
COUNTED_TOPICS = ["/tf", "/simulator/momentum", "/simulator/body_states"]

_children = []  # Popen objects of the process groups we started


def stop_group(proc, timeout=10.0):
    """SIGINT to the process group, then SIGTERM, then SIGKILL."""
    if proc is None or proc.poll() is not None:
        return
    for sig, wait in ((signal.SIGINT, timeout), (signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        try:
            proc.wait(wait)
            break
        except subprocess.TimeoutExpired:
            continue
    # Children of the group that outlived their leader (roscore's rosmaster, rosout).
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def cleanup():
    while _children:
        stop_group(_children.pop())


def on_signal(signum, _frame):
    cleanup()
    sys.exit(128 + signum)


def start(cmd, log_path, env):
    log = open(log_path, "w")
    proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env,
                            start_new_session=True)
    log.close()
    _children.append(proc)
    return proc


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def write_csv(path, rows):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in COLUMNS})


def skipped_rows(ns, rtfs, args, why):
    return [{"n_bodies": n, "real_time_factor": rtf, "publish_rate_hz": args.publish_rate,
             "integrator": args.integrator, "dt": args.dt, "status": why}
            for n in ns for rtf in rtfs]


# ---------------------------------------------------------------------------------------------
# The scene
# ---------------------------------------------------------------------------------------------

def fallback_scene(n, urdf_path, state_path):
    """N free boxes on a grid, each with its own spin (as scripts/generate_many_bodies.py)."""
    size, mass = (0.2, 0.15, 0.1), 1.0
    x, y, z = size
    ixx, iyy, izz = (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12,
                     mass * (x * x + y * y) / 12)
    side = 1
    while side ** 3 < n:
        side += 1
    with open(urdf_path, "w") as f:
        f.write('<?xml version="1.0"?>\n<robot name="many_bodies">\n  <link name="world"/>\n')
        for k in range(n):
            px, py, pz = k % side, (k // side) % side, 1 + k // (side * side)
            f.write('  <joint name="box_%d_float" type="floating"><parent link="world"/>'
                    '<child link="box_%d"/><origin xyz="%d %d %d"/></joint>\n'
                    '  <link name="box_%d"><inertial><mass value="%r"/><inertia ixx="%r" '
                    'ixy="0" ixz="0" iyy="%r" iyz="0" izz="%r"/></inertial></link>\n'
                    % (k, k, px, py, pz, k, mass, ixx, iyy, izz))
        f.write("</robot>\n")
    with open(state_path, "w") as f:
        f.write("initial_state:\n")
        for k in range(n):
            w = (3 * math.sin(1.3 * k + 0.1), 3 * math.cos(0.7 * k + 0.2),
                 3 * math.sin(0.37 * k + 1.0))
            f.write("  box_%d:\n    angular_velocity: [%.6f, %.6f, %.6f]\n" % ((k,) + w))


def make_scene(n, tmp):
    urdf, state = os.path.join(tmp, "many_%d.urdf" % n), os.path.join(tmp, "many_%d.yaml" % n)
    gen = os.path.join(ROOT, "scripts", "generate_many_bodies.py")
    if os.path.exists(gen):
        with open(urdf, "w") as f:
            subprocess.run([sys.executable, gen, str(n)], stdout=f, check=True)
        with open(state, "w") as f:
            subprocess.run([sys.executable, gen, str(n), "--initial-state"], stdout=f, check=True)
    else:
        print("node_throughput: scripts/generate_many_bodies.py missing: generating the scene "
              "here", file=sys.stderr)
        fallback_scene(n, urdf, state)
    return urdf, state


# ---------------------------------------------------------------------------------------------
# Measuring
# ---------------------------------------------------------------------------------------------

class Monitor:
    """/clock samples (wall time of arrival, sim time), in rospy (100 Hz: cheap)."""

    def __init__(self, rospy, Clock):
        self.lock = threading.Lock()
        self.last_clock = None  # (wall, sim)
        self.sub = rospy.Subscriber("/clock", Clock, self.on_clock, queue_size=1,
                                    tcp_nodelay=True)

    def on_clock(self, msg):
        now = time.monotonic()
        with self.lock:
            self.last_clock = (now, msg.clock.to_sec())

    def clock(self):
        with self.lock:
            return self.last_clock

    def reset(self):
        with self.lock:
            self.last_clock = None


class CounterProcess:
    """Message and byte counts of COUNTED_TOPICS from bench_topic_counter, which prints a line
    "counts <monotonic s> <msgs> <bytes> ..." every 100 ms; the latest line is kept."""

    name = "bench_topic_counter"

    def __init__(self, path, log_path, env):
        self.lock = threading.Lock()
        self.time = time.monotonic()
        self.counts = [0] * (2 * len(COUNTED_TOPICS))
        self.log_path = log_path
        self.proc = subprocess.Popen([path] + COUNTED_TOPICS, stdout=subprocess.PIPE,
                                     stderr=open(log_path, "w"), env=env,
                                     start_new_session=True, text=True)
        _children.append(self.proc)
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for line in self.proc.stdout:
            fields = line.split()
            if len(fields) == 2 + len(self.counts) and fields[0] == "counts":
                with self.lock:
                    self.time = float(fields[1])
                    self.counts = [int(x) for x in fields[2:]]

    def snapshot(self):
        """(monotonic time of the counts, [(messages, bytes) per topic]), cumulative."""
        if self.proc.poll() is not None:
            raise RuntimeError("bench_topic_counter exited with code %d (log: %s)" % (
                self.proc.returncode, self.log_path))
        with self.lock:
            t, c = self.time, list(self.counts)
        return t, [(c[2 * i], c[2 * i + 1]) for i in range(len(COUNTED_TOPICS))]


class RospyCounter:
    """The fallback when bench_topic_counter is not built: rospy raw (AnyMsg) subscribers."""

    name = "rospy AnyMsg"

    def __init__(self, rospy, AnyMsg):
        self.lock = threading.Lock()
        self.counts = [[0, 0] for _ in COUNTED_TOPICS]
        self.subs = [rospy.Subscriber(t, AnyMsg, self._counter(i), queue_size=1,
                                      tcp_nodelay=True)
                     for i, t in enumerate(COUNTED_TOPICS)]

    def _counter(self, i):
        def on_msg(msg):
            with self.lock:
                self.counts[i][0] += 1
                self.counts[i][1] += len(msg._buff)
        return on_msg

    def snapshot(self):
        with self.lock:
            return time.monotonic(), [tuple(c) for c in self.counts]


def node_threads(log_path):
    """The thread count from the node's first log line ("simulator: dt ... s; N threads; ...")."""
    try:
        with open(log_path) as f:
            for line in f:
                m = re.search(r"simulator: dt [^;]*; (\d+) threads?;", line)
                if m:
                    return m.group(1)
    except OSError:
        pass
    return ""


def measure(rospy, monitor, counter, node_proc, args, n, rtf, urdf, state_yaml, tmp, env,
            integrator):
    import yaml  # python3-yaml, a rospy dependency

    name = "simulator"
    if rospy.has_param("/" + name):
        rospy.delete_param("/" + name)
    initial = None
    if state_yaml:
        with open(state_yaml) as f:
            initial = (yaml.safe_load(f) or {}).get("initial_state")
    params = {"urdf_file": urdf, "real_time_factor": float(rtf), "dt": args.dt,
              "integrator": integrator, "publish_rate": args.publish_rate,
              "publish_clock": True, "clock_rate": args.publish_rate}
    params.update(args.node_params)
    if initial:
        params["initial_state"] = initial
    rospy.set_param("/" + name, params)
    monitor.reset()
    row = {"n_bodies": n, "real_time_factor": rtf, "publish_rate_hz": args.publish_rate,
           "integrator": integrator, "dt": args.dt, "subscriber": counter.name}
    log_path = os.path.join(tmp, "node_%d_%s_%s.log" % (n, rtf, integrator))
    proc = start([node_proc, "__name:=" + name], log_path, env)
    try:
        # Up: the first /clock after t = 0 (loading 10 000 bodies takes a while).
        deadline = time.monotonic() + args.start_timeout
        while True:
            clock = monitor.clock()
            if clock is not None and clock[1] > 0:
                break
            if proc.poll() is not None:
                row["status"] = "node exited with code %d at start (log: %s)" % (
                    proc.returncode, log_path)
                return row
            if time.monotonic() > deadline:
                row["status"] = "no /clock within %g s (log: %s)" % (args.start_timeout, log_path)
                return row
            time.sleep(0.05)
        row["threads"] = node_threads(log_path)
        time.sleep(args.warmup)
        c0, n0 = monitor.clock(), counter.snapshot()
        time.sleep(args.window)
        c1, n1 = monitor.clock(), counter.snapshot()
        if proc.poll() is not None:
            row["status"] = "node exited with code %d (log: %s)" % (proc.returncode, log_path)
            return row
        wall = c1[0] - c0[0]
        sim = c1[1] - c0[1]
        if not (wall > 0 and sim > 0):
            row["status"] = "simulated time did not advance during the window"
            return row
        rate = sim / wall
        steps = rate / args.dt
        if float(rtf) == 0:  # as fast as possible: the wall time per body-step
            row["ns_per_body_step"] = "%.6g" % (1e9 / (steps * n))
        # Received per second over the time between the two counts.
        (t0, n0), (t1, n1) = n0, n1
        span = max(t1 - t0, 1e-9)
        per_s = [(m1 - m0) / span for (m0, _), (m1, _) in zip(n0, n1)]
        mb_per_s = [(b1 - b0) / span / 1e6 for (_, b0), (_, b1) in zip(n0, n1)]
        row.update({"window_s": "%.3f" % wall, "sim_s": "%.4f" % sim,
                    "steps_per_s": "%.6g" % steps, "achieved_rtf": "%.6g" % rate,
                    "tf_received_per_s": "%.4g" % per_s[0],
                    "tf_received_mb_per_s": "%.4g" % mb_per_s[0],
                    "momentum_received_per_s": "%.4g" % per_s[1],
                    "body_states_received_per_s": "%.4g" % per_s[2],
                    "body_states_received_mb_per_s": "%.4g" % mb_per_s[2],
                    "status": "ok"})
        return row
    finally:
        stop_group(proc)
        if proc in _children:
            _children.remove(proc)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ns", default="1,100,1000,10000")
    ap.add_argument("--rtfs", default="0,1", help="~real_time_factor values (0 = max speed)")
    ap.add_argument("--window", type=float, default=8.0, help="measuring window, wall s")
    ap.add_argument("--warmup", type=float, default=2.0, help="wall s after the first /clock")
    ap.add_argument("--start-timeout", type=float, default=120.0)
    ap.add_argument("--publish-rate", type=float, default=100.0)
    ap.add_argument("--dt", type=float, default=0.001)
    ap.add_argument("--integrator", default="auto")
    ap.add_argument("--extra", default="10000:cga2",
                    help="more runs N:integrator[,N:integrator] (both real-time factors); "
                         "'' for none")
    ap.add_argument("--node", default=DEFAULT_NODE)
    ap.add_argument("--counter", default=None,
                    help="the subscriber that counts (default: bench_topic_counter next to "
                         "--node, else in this checkout's build); if absent, rospy counts")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "out"))
    ap.add_argument("--threads", type=int, default=0,
                    help="~threads of the node (0: its default, the cores available)")
    ap.add_argument("--atlas", action="store_true",
                    help="Atlas (dart-doc) falling onto ~ground_plane instead of free boxes")
    ap.add_argument("--ground-shift", type=float, default=0.0,
                    help="--atlas: metres the plane is lowered below its case height (another "
                         "start: the landing is chaotic; bench_contacts --robots --starts)")
    args = ap.parse_args()
    args.node_params = {}
    if args.atlas:
        if not os.path.isfile(ATLAS_URDF):
            print("node_throughput: skipped: %s is absent (Debian package dart-doc)" % ATLAS_URDF,
                  file=sys.stderr)
            return 0
        args.ns, args.extra = str(ATLAS_BODIES), ""
        if "--warmup" not in sys.argv:
            args.warmup = 0.0
        if not (math.isfinite(args.ground_shift) and args.ground_shift >= 0):
            print("node_throughput: --ground-shift wants a distance >= 0 in metres",
                  file=sys.stderr)
            return 2
        args.node_params = {"ground_plane": {"height": ATLAS_GROUND_Z - args.ground_shift},
                            "self_collision": "auto"}
    if args.threads > 0:
        args.node_params["threads"] = args.threads
    ns = [int(x) for x in args.ns.split(",") if x]
    rtfs = [x for x in args.rtfs.split(",") if x]
    runs = [(n, args.integrator) for n in ns]  # (N, integrator), in order
    for item in [x for x in args.extra.split(",") if x]:
        n, integrator = item.split(":")
        runs.append((int(n), integrator))
    csv_path = os.path.join(args.out,
                            "node_throughput_atlas.csv" if args.atlas else "node_throughput.csv")
    if args.counter is None:
        beside = os.path.join(os.path.dirname(os.path.abspath(args.node)), "bench_topic_counter")
        args.counter = beside if os.path.isfile(beside) else DEFAULT_COUNTER

    if not (os.path.isfile(args.node) and os.access(args.node, os.X_OK)):
        why = "skipped: the node is not built (%s)" % os.path.relpath(args.node, ROOT)
        print("node_throughput: %s; build with scripts/build.sh" % why, file=sys.stderr)
        write_csv(csv_path, skipped_rows(ns, rtfs, args, why))
        return 0
    try:
        import rospy
        import rosgraph
        from rosgraph_msgs.msg import Clock
    except ImportError as e:
        why = "skipped: rospy not available (%s)" % e
        print("node_throughput: " + why, file=sys.stderr)
        write_csv(csv_path, skipped_rows(ns, rtfs, args, why))
        return 0
    if shutil.which("roscore") is None:
        why = "skipped: roscore not found"
        print("node_throughput: " + why, file=sys.stderr)
        write_csv(csv_path, skipped_rows(ns, rtfs, args, why))
        return 0

    atexit.register(cleanup)
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)

    tmp = tempfile.mkdtemp(prefix="cga_node_throughput_")
    port = free_port()
    env = dict(os.environ)
    env.update({"ROS_MASTER_URI": "http://127.0.0.1:%d" % port, "ROS_IP": "127.0.0.1",
                "ROS_HOME": tmp, "ROS_LOG_DIR": os.path.join(tmp, "log"),
                # the node's log lines reach its log file at once (node_threads reads them)
                "ROSCONSOLE_STDOUT_LINE_BUFFERED": "1"})
    env.pop("ROS_HOSTNAME", None)
    os.environ.update({k: env[k] for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOME",
                                           "ROS_LOG_DIR")})
    os.environ.pop("ROS_HOSTNAME", None)

    rows = []
    try:
        core = start(["roscore", "-p", str(port)], os.path.join(tmp, "roscore.log"), env)
        master = rosgraph.Master("/bench_node_throughput", master_uri=env["ROS_MASTER_URI"])
        deadline = time.monotonic() + 30
        while True:
            try:
                master.getPid()
                break
            except Exception:  # not up yet
                if core.poll() is not None or time.monotonic() > deadline:
                    why = "skipped: roscore did not start (log: %s)" % os.path.join(
                        tmp, "roscore.log")
                    print("node_throughput: " + why, file=sys.stderr)
                    write_csv(csv_path, skipped_rows(ns, rtfs, args, why))
                    return 0
                time.sleep(0.2)
        from rospy.msg import AnyMsg
        rospy.init_node("bench_node_throughput", anonymous=True, disable_signals=True)
        monitor = Monitor(rospy, Clock)
        if os.path.isfile(args.counter) and os.access(args.counter, os.X_OK):
            counter = CounterProcess(args.counter, os.path.join(tmp, "counter.log"), env)
        else:
            print("node_throughput: %s not built: counting with rospy, which takes CPU from "
                  "the node" % os.path.relpath(args.counter, ROOT), file=sys.stderr)
            counter = RospyCounter(rospy, AnyMsg)
        scenes = {}
        for n, integrator in runs:
            if n not in scenes:
                scenes[n] = (ATLAS_URDF, None) if args.atlas else make_scene(n, tmp)
            urdf, state = scenes[n]
            for rtf in rtfs:
                t0 = time.monotonic()
                row = measure(rospy, monitor, counter, args.node, args, n, rtf, urdf, state,
                              tmp, env, integrator)
                rows.append(row)
                write_csv(csv_path, rows)
                if row.get("status") == "ok":
                    print("[node] %-5s N=%-6d rtf=%-3s threads %s %10.0f steps/s  achieved RTF "
                          "%8.3f  received: tf %5s/s, momentum %5s/s, body_states %5s/s  (%.0f s)"
                          % (integrator, n, rtf, row["threads"] or "?",
                             float(row["steps_per_s"]), float(row["achieved_rtf"]),
                             row["tf_received_per_s"], row["momentum_received_per_s"],
                             row["body_states_received_per_s"], time.monotonic() - t0),
                          file=sys.stderr)
                else:
                    print("[node] %s N=%d rtf=%s: %s" % (integrator, n, rtf, row["status"]),
                          file=sys.stderr)
    finally:
        try:
            import rospy as _r
            if _r.core.is_initialized():
                _r.signal_shutdown("done")
        except Exception:
            pass
        cleanup()
        if rows and all(r.get("status") == "ok" for r in rows):
            shutil.rmtree(tmp, ignore_errors=True)
        else:
            print("node_throughput: logs kept in " + tmp, file=sys.stderr)
    write_csv(csv_path, rows)
    print("node_throughput: wrote " + csv_path, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
