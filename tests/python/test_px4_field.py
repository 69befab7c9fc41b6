"""PX4 field interface (issue 52 part 4): px4_bridge flies a path through a
peer that plays PX4 v1.15 over its uXRCE-DDS topics (nodes/examples/px4_peer.rs:
offboard only after a ≥ 2 Hz heartbeat, set-mode and arm; a point mass in NED).
rclpy publishes /uav/global_path (map ENU) and watches /uav/state_estimation
and /uav/vehicle_status, as a planner would."""
import json
import math
import time

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry, Path
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

# Where PX4's NED origin (its home) lies in the map: not the map's origin, so
# a wrong or missing offset shows.
HOME = (12.0, -4.0, 1.5)
# Up 10 m, 10 m east, then 10 m north climbing 3 m (map ENU, heading).
WAY_POINTS = [((12.0, -4.0, 11.5), 0.0), ((22.0, -4.0, 11.5), 0.0), ((22.0, 6.0, 14.5), math.pi / 2)]
# config/px4_bridge.yaml: follow.waypoint_radius_m, follow.goal_tolerance_m.
RADIUS, GOAL_TOLERANCE = 1.5, 1.0


def path_msg(stamp, points):
    m = Path()
    m.header.frame_id = "map"
    m.header.stamp = stamp
    for (x, y, z), yaw in points:
        ps = PoseStamped()
        ps.header = m.header
        ps.pose.position.x, ps.pose.position.y, ps.pose.position.z = x, y, z
        ps.pose.orientation.z, ps.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
        m.poses.append(ps)
    return m


def ned_of(enu):
    """Map ENU → PX4 NED with the origin at HOME."""
    e, n, u = (enu[0] - HOME[0], enu[1] - HOME[1], enu[2] - HOME[2])
    return (n, e, -u)


def test_px4_bridge_flies_a_path_through_a_px4_peer(tmp_path, spawn, ros):
    peer_log = tmp_path / "peer.jsonl"
    # Every 25th odometry is bad (NaN, or an FRD frame 1 km off): skipped, never shown.
    peer = spawn("examples/px4_peer", "--log", peer_log, "--bad-every", "25")
    assert peer.json_lines(1, timeout=30)[0]["event"] == "ready"
    home = "[" + ", ".join(map(str, HOME)) + "]"
    bridge = spawn("px4_bridge", "--ros-args", "-p", f"offboard.home_map:={home}")
    poses, statuses = [], []
    node = ros.node
    node.create_subscription(Odometry, "/uav/state_estimation", poses.append,
                             QoSProfile(depth=50, reliability=ReliabilityPolicy.BEST_EFFORT))
    node.create_subscription(DiagnosticArray, "/uav/vehicle_status", statuses.append, 10)
    latched = QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
    pub = node.create_publisher(Path, "/uav/global_path", latched)
    t0 = time.time()
    assert ros.spin_until(lambda: len(poses) > 5, 20), "no /uav/state_estimation: " + bridge.stderr()[-2000:]
    # A NaN way-point: the path is refused with a log line, the bridge goes on.
    bad = [WAY_POINTS[0], ((float("nan"), 0.0, 10.0), 0.0)]
    pub.publish(path_msg(node.get_clock().now().to_msg(), bad))
    assert ros.spin_until(lambda: "refused" in bridge.stderr(), 10), bridge.stderr()[-2000:]
    assert "way-point 1 of 2 is not finite" in bridge.stderr()
    ros.spin_until(lambda: False, 1.0)
    first_good = len(poses)
    pub.publish(path_msg(node.get_clock().now().to_msg(), WAY_POINTS))
    arrived = lambda: any(s.message == "arrived" for a in statuses for s in a.status)  # noqa: E731
    assert ros.spin_until(arrived, 40), f"no arrival; bridge:\n{bridge.stderr()[-3000:]}"
    wall = time.time() - t0
    assert bridge.p.poll() is None, "the bridge keeps running"
    bridge.stop()
    peer.stop()
    log = bridge.log_path.read_text(errors="replace")
    events = [json.loads(line) for line in peer_log.read_text().splitlines() if line.strip()]
    report = f"\nbridge:\n{log[-2500:]}\npeer commands: {[e for e in events if e['event'] == 'command']}"

    # The peer saw the heartbeat at ≥ 2 Hz, offboard and arming, before it moved.
    cmds = [e for e in events if e["event"] == "command"]
    mode = [c for c in cmds if c["command"] == 176 and c["accepted"]]
    arm = [c for c in cmds if c["command"] == 400 and c["accepted"]]
    assert mode and arm, report
    assert mode[0]["heartbeat_hz"] >= 2, report
    moved = [e for e in events if e["event"] == "first_move"]
    assert moved, report
    assert moved[0]["t"] > max(mode[0]["t"], arm[0]["t"]), report
    assert moved[0]["armed"] and moved[0]["nav_state"] == 14 and moved[0]["heartbeat_hz"] >= 2, moved[0]

    # Every pose the bridge published is one the peer sent, converted NED → ENU.
    good = np.array([e["ned"] for e in events if e["event"] == "odom" and not e["bad"]])
    bad_sent = sum(e["event"] == "odom" and e["bad"] for e in events)
    assert bad_sent > 10
    enu = np.array([[p.pose.pose.position.x, p.pose.pose.position.y, p.pose.pose.position.z] for p in poses])
    ned = np.array([ned_of(p) for p in enu])
    worst = max(np.abs(good - q).max(axis=1).min() for q in ned[:: max(1, len(ned) // 300)])
    assert worst < 1e-3, f"a published pose is no peer odometry converted: {worst} m off"
    assert all(p.header.frame_id == "map" and p.child_frame_id == "uav/base_link" for p in poses)

    # Every way-point reached within its radius, in order.
    flown = enu[first_good:]
    at = 0
    for i, ((x, y, z), _) in enumerate(WAY_POINTS):
        radius = GOAL_TOLERANCE if i == len(WAY_POINTS) - 1 else RADIUS
        d = np.linalg.norm(flown[at:] - np.array([x, y, z]), axis=1)
        hits = np.nonzero(d <= radius)[0]
        assert len(hits), f"way-point {i} never within {radius} m (closest {d.min():.2f} m)"
        at += int(hits[0])
    # The status is robot_bridge's wording, with the odometer.
    status = next(s for a in statuses for s in a.status if s.message == "arrived")
    values = {kv.key: kv.value for kv in status.values}
    flown_m = float(values["odometer_m"])
    print(f"\npx4 field: {len(poses)} poses, {bad_sent} bad odometry skipped, flew {flown_m:.1f} m, "
          f"offboard at {mode[0]['t']:.1f} s (heartbeat {mode[0]['heartbeat_hz']} Hz), {wall:.1f} s wall")
    # The path is 30.4 m; corners are cut within the way-point radius and the goal reached 1 m short.
    assert 0.8 * (10.0 + 10.0 + math.hypot(10, 3)) < flown_m < 40, values
    assert "asking PX4: SetOffboard (command 176)" in log and "asking PX4: Arm (command 400)" in log, log[-2000:]
    assert "arrived at (22.0, 6.0, 14.5)" in log, log[-2000:]
