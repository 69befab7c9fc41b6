"""Shared fixtures: skyground binaries as processes, rclpy in a domain of each
test's own, and a guard that DDS tests only run in a loopback-only namespace."""
import itertools
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BIN = Path(os.environ.get("SKYGROUND_BIN_DIR", ROOT / "target" / "debug"))
REAL = Path(os.environ.get("SKYGROUND_REAL_DATA", ROOT.parent / "shared" / "data" / "real"))
PEER = ROOT / "tests" / "python" / "peer_cloud.py"

# Let this process's Fast DDS take bursts of large clouds (see docs/transport.md).
os.environ.setdefault("FASTDDS_BUILTIN_TRANSPORTS", "DEFAULT?sockets_size=4194304")
os.environ.setdefault("ROS_DISTRO", "kilted")

_domains = itertools.count(int(os.environ.get("SKYGROUND_TEST_DOMAIN_BASE", "40")))


def isolated():
    with open("/proc/net/dev") as f:
        names = [line.split(":")[0].strip() for line in f.readlines()[2:]]
    return names == ["lo"]


def ephemeral_from():
    with open("/proc/sys/net/ipv4/ip_local_port_range") as f:
        return int(f.read().split()[0])


# The highest port a participant of domain d binds: 7400 + 250 d + 10 + 2 * (participant id < 20) + 1.
def highest_dds_port(domain):
    return 7400 + 250 * domain + 51


@pytest.fixture(scope="session", autouse=True)
def _guard_network():
    if not isolated():
        pytest.exit("DDS tests must run in a loopback-only network namespace: use tests/run_all.sh "
                    "(or tests/netns.sh python -m pytest ...)", returncode=3)
    # A DDS port inside the ephemeral range can be taken by any socket bound to port 0, and then a
    # participant is never discovered (rarely: test_explore_region timed out once in CI).
    last = int(os.environ.get("SKYGROUND_TEST_DOMAIN_BASE", "40")) + 150
    if highest_dds_port(last) >= ephemeral_from():
        pytest.exit(f"the ephemeral port range starts at {ephemeral_from()}, below the DDS ports of the test "
                    f"domains (up to {highest_dds_port(last)}): run through tests/netns.sh, which moves it",
                    returncode=3)


def real_file(name):
    path = REAL / name
    if not path.exists():
        pytest.skip(f"real data not found: {path} (../shared/data/real is absent)")
    return path


# A node whose DDS creation deadlocked exits with this (nodes/src/runtime/creation_watch.rs).
EXIT_STUCK = 75


class Proc:
    """A skyground binary run as a child process in the test's domain. One that
    exits with EXIT_STUCK is started again, up to `respawns` times, as ros2
    launch's respawn=True does (README, "DDS safety")."""

    def __init__(self, args, env, log_path, respawns=2):
        self.args = args
        self.env = env
        self.log_path = log_path
        self.restarts = 0
        self._respawns = respawns
        self._stopping = False
        self._lock = threading.Lock()
        self._log = open(log_path, "wb")
        self.p = self._popen()
        if respawns > 0:
            threading.Thread(target=self._respawn_stuck, daemon=True).start()

    def _popen(self):
        return subprocess.Popen(self.args, env=self.env, stdout=subprocess.PIPE, stderr=self._log)

    def _respawn_stuck(self):
        while True:
            p = self.p
            rc = p.wait()
            with self._lock:
                if self._stopping or rc != EXIT_STUCK or self.restarts >= self._respawns:
                    return
                self.restarts += 1
                self._log.write(f"[harness] exited {rc}; starting it again ({self.restarts})\n".encode())
                self._log.flush()
                self.p = self._popen()

    def _respawn_pending(self, rc):
        with self._lock:
            return rc == EXIT_STUCK and self.restarts < self._respawns and not self._stopping

    def stop(self, sig=signal.SIGINT, timeout=10.0):
        with self._lock:
            self._stopping = True
        if self.p.poll() is None:
            self.p.send_signal(sig)
            try:
                self.p.wait(timeout)
            except subprocess.TimeoutExpired:
                self.p.kill()
                self.p.wait()
        self._log.close()
        return self.p.returncode

    def stderr(self):
        self._log.flush()
        return Path(self.log_path).read_text(errors="replace")

    def json_lines(self, n, timeout=60.0):
        """Reads n JSON lines from stdout (raises on timeout)."""
        out = []
        end = time.time() + timeout
        p, buf = None, b""
        while len(out) < n:
            if time.time() > end:
                raise TimeoutError(f"{self.args[0]}: got {len(out)} of {n} lines; stderr:\n{self.stderr()[-3000:]}")
            if p is not self.p:
                # Started again: a line cut short by the exit is dropped.
                p, buf = self.p, b""
                os.set_blocking(p.stdout.fileno(), False)
            chunk = p.stdout.read()
            if chunk:
                buf += chunk
                *lines, buf = buf.split(b"\n")
                out.extend(json.loads(line) for line in lines if line.strip())
            elif p.poll() is not None and p is self.p and not self._respawn_pending(p.returncode):
                raise RuntimeError(f"{self.args[0]} exited {p.returncode}; stderr:\n{self.stderr()[-3000:]}")
            else:
                time.sleep(0.02)
        return out


@pytest.fixture
def domain():
    return next(_domains)


@pytest.fixture
def env(domain):
    e = dict(os.environ)
    e["ROS_DOMAIN_ID"] = str(domain)
    e.pop("RUST_LOG", None)
    return e


@pytest.fixture
def spawn(env, tmp_path):
    procs = []

    def start(name, *args, extra_env=None, respawns=2):
        exe = str(BIN / name) if not name.endswith(".py") else sys.executable
        argv = [exe, *map(str, args)] if not name.endswith(".py") else [exe, name, *map(str, args)]
        e = dict(env, **(extra_env or {}))
        p = Proc(argv, e, tmp_path / f"{Path(name).name}-{len(procs)}.log", respawns)
        procs.append(p)
        return p

    yield start
    for p in procs:
        p.stop()


@pytest.fixture
def ros(domain):
    """An rclpy context and node in the test's domain."""
    import rclpy
    from rclpy.node import Node

    ctx = rclpy.Context()
    rclpy.init(context=ctx, domain_id=domain)
    node = Node(f"pytest_{domain}", context=ctx)
    executor = rclpy.executors.SingleThreadedExecutor(context=ctx)
    executor.add_node(node)

    class Ros:
        pass

    r = Ros()
    r.node, r.ctx, r.executor = node, ctx, executor

    def spin_until(pred, timeout=30.0):
        end = time.time() + timeout
        while time.time() < end:
            if pred():
                return True
            executor.spin_once(timeout_sec=0.05)
        return pred()

    r.spin_until = spin_until
    yield r
    executor.shutdown()
    node.destroy_node()
    rclpy.shutdown(context=ctx)


def qos(kind="reliable", depth=10):
    """latched, reliable or sensor, as peer_cloud.py (and any rclpy user) says it."""
    from peer_cloud import qos as peer_qos

    return peer_qos(kind, depth)


def record_live_bag(ros, spawn, bag, points, path_xy, odom_x, gap):
    """Records a live session into `bag` with `skyground record`: /aerial_cloud
    from a cloud_publisher of `points` points, a latched /global_path through
    `path_xy` and /state_estimation at x = each of `odom_x`, `gap` s apart.
    On return the recorder has stopped cleanly and this node's publishers are
    gone; the cloud publisher is returned (still running)."""
    from geometry_msgs.msg import PoseStamped
    from nav_msgs.msg import Odometry, Path as NavPath

    path_pub = ros.node.create_publisher(NavPath, "/global_path", qos("latched", 1))
    odom_pub = ros.node.create_publisher(Odometry, "/state_estimation", qos("reliable", 10))
    source = spawn("cloud_publisher", "--ros-args", "-p", f"synthetic_points:={points}")
    rec = spawn("skyground", "record", "-o", bag, "/aerial_cloud", "/global_path", "/state_estimation")
    path = NavPath()
    path.header.frame_id = "map"
    for x, y in path_xy:
        p = PoseStamped()
        p.pose.position.x, p.pose.position.y = float(x), float(y)
        path.poses.append(p)
    path_pub.publish(path)
    # Odometry is volatile: publish once the recorder subscribes.
    assert ros.spin_until(lambda: odom_pub.get_subscription_count() > 0, 30), rec.stderr()
    for x in odom_x:
        o = Odometry()
        o.header.frame_id = "map"
        o.pose.pose.position.x = float(x)
        odom_pub.publish(o)
        ros.spin_until(lambda: False, gap)
    ros.spin_until(lambda: False, 2.0)
    assert rec.stop(signal.SIGINT) == 0, rec.stderr()
    ros.node.destroy_publisher(path_pub)
    ros.node.destroy_publisher(odom_pub)
    return source
