"""Clouds between skyground's Rust nodes and real rclpy (Fast DDS), both ways."""
import time

import numpy as np
import pytest

from conftest import PEER, qos, real_file


def receive_clouds(ros, topic, kind, count, timeout=60.0, tile_points=65536):
    """Subscribes like a plain rclpy user and reassembles skyground's tiles."""
    from sensor_msgs.msg import PointCloud2

    groups, done = {}, []

    def on_msg(m):
        key = (m.header.stamp.sec, m.header.stamp.nanosec)
        groups.setdefault(key, []).append(m)
        if m.width != tile_points:
            done.append(groups.pop(key))

    ros.node.create_subscription(PointCloud2, topic, on_msg, qos(kind, depth=300))
    assert ros.spin_until(lambda: len(done) >= count, timeout), f"got {len(done)} of {count} clouds on {topic}"
    return done


def fields_of(msgs):
    from peer_cloud import to_arrays

    xyz, label = zip(*(to_arrays(m) for m in msgs))
    return np.concatenate(xyz), (None if label[0] is None else np.concatenate(label))


def test_sample_las_reaches_rclpy_with_counts_and_labels(spawn, ros):
    import laspy

    path = real_file("sample_c.las")
    las = laspy.read(str(path))
    spawn("cloud_publisher", "--ros-args", "-p", f"file:={path}")
    (tiles,) = receive_clouds(ros, "/aerial_cloud", "latched", 1)
    xyz, label = fields_of(tiles)
    assert len(xyz) == len(las.points) == 14408
    np.testing.assert_array_equal(label, np.asarray(las.classification, dtype=np.uint8))
    want = np.stack([las.x, las.y, las.z], axis=1)
    # The cloud is in a local frame: compare positions relative to the first point.
    np.testing.assert_allclose(xyz - xyz[0], want - want[0], atol=2e-3)
    assert {f.name for f in tiles[0].fields} >= {"x", "y", "z", "intensity", "label"}
    assert tiles[0].header.frame_id == "map"


def test_rust_receives_rclpy_path_intact(spawn, ros):
    from geometry_msgs.msg import PoseStamped
    from nav_msgs.msg import Path

    path = Path()
    path.header.frame_id = "map"
    path.header.stamp.sec, path.header.stamp.nanosec = 1234, 5678
    for i in range(25):
        p = PoseStamped()
        p.header.frame_id = "map"
        p.header.stamp.sec = i
        p.pose.position.x, p.pose.position.y, p.pose.position.z = i * 1.5, -i * 0.25, 0.125 + i
        p.pose.orientation.z, p.pose.orientation.w = 0.6, 0.8
        path.poses.append(p)
    pub = ros.node.create_publisher(Path, "/global_path", qos("latched", 1))
    pub.publish(path)
    echo = spawn("skyground", "echo", "/global_path", "--type", "nav_msgs/msg/Path", "--qos", "latched",
                 "--count", "1", "--timeout", "30")
    got = None

    def arrived():
        nonlocal got
        try:
            got = echo.json_lines(1, timeout=0.1)[0]
        except TimeoutError:
            return False
        return True

    assert ros.spin_until(arrived, 40), echo.stderr()
    msg = got["msg"]
    assert msg["header"] == {"stamp": {"sec": 1234, "nanosec": 5678}, "frame_id": "map"}
    assert len(msg["poses"]) == 25
    for i, p in enumerate(msg["poses"]):
        assert p["header"]["stamp"]["sec"] == i
        assert p["pose"]["position"] == {"x": i * 1.5, "y": -i * 0.25, "z": 0.125 + i}
        assert p["pose"]["orientation"] == {"x": 0.0, "y": 0.0, "z": 0.6, "w": 0.8}


N5M = 5_000_000


def test_5m_points_rust_to_rclpy_whole(spawn, env):
    sink = spawn(str(PEER), "sink", "--topic", "/big", "--count", "2", "--check-synthetic", "--timeout", "120")
    assert sink.json_lines(1, 60)[0] == {"ready": True}
    pub = spawn("cloud_publisher", "--ros-args", "-p", "topic:=/big", "-p", f"synthetic_points:={N5M}",
                "-p", "count:=2", "-p", "wait_for_subscribers:=1", "-p", "period_s:=0.5")
    clouds = sink.json_lines(2, 120)
    assert [c["points"] for c in clouds] == [N5M, N5M], pub.stderr()
    assert all(c["valid"] for c in clouds), "points differ from what was sent"
    assert clouds[0]["tiles"] == N5M // 65536 + 1


def test_5m_points_rclpy_to_rust_whole(spawn):
    sink = spawn("skyground", "cloud-sink", "--topic", "/big", "--count", "2", "--check-synthetic")
    assert sink.json_lines(1, 60)[0] == {"ready": True}
    spawn(str(PEER), "send", "--topic", "/big", "--points", str(N5M), "--count", "2", "--linger", "60")
    clouds = sink.json_lines(2, 120)
    assert [c["points"] for c in clouds] == [N5M, N5M]
    assert all(c["valid"] for c in clouds)
    assert all(c["bytes"] == 16 * N5M for c in clouds)


def test_5m_points_rust_to_rust_whole(spawn):
    sink = spawn("skyground", "cloud-sink", "--topic", "/big", "--count", "2", "--check-synthetic")
    assert sink.json_lines(1, 60)[0] == {"ready": True}
    spawn("cloud_publisher", "--ros-args", "-p", "topic:=/big", "-p", f"synthetic_points:={N5M}",
          "-p", "count:=2", "-p", "wait_for_subscribers:=1", "-p", "period_s:=0.5")
    clouds = sink.json_lines(2, 120)
    assert [c["points"] for c in clouds] == [N5M, N5M]
    assert all(c["valid"] for c in clouds)


def good_cloud(n=100):
    from peer_cloud import synthetic
    from sensor_msgs.msg import PointCloud2, PointField

    xyz, _ = synthetic(n)
    m = PointCloud2()
    m.header.frame_id = "map"
    m.height, m.width = 1, n
    m.fields = [PointField(name=c, offset=4 * i, datatype=PointField.FLOAT32, count=1) for i, c in enumerate("xyz")]
    m.point_step, m.row_step, m.is_dense = 12, 12 * n, True
    m.data = xyz.astype(np.float32).tobytes()
    return m


def malformed_cases():
    from sensor_msgs.msg import PointField

    def case(name, expect, change):
        m = good_cloud()
        change(m)
        return pytest.param(m, expect, id=name)

    def drop_z(m):
        m.fields = m.fields[:2]

    def bad_type(m):
        m.fields[1].datatype = 42

    def bad_count(m):
        m.fields[0].count = 2

    def small_step(m):
        m.point_step, m.row_step = 8, 8 * m.width
        m.data = bytes(m.data)[: 8 * m.width]

    def small_row(m):
        m.row_step = 12 * m.width - 1

    def bad_len(m):
        m.data = bytes(m.data)[:-5]

    def big_endian(m):
        m.is_bigendian = True

    def overflow(m):
        m.width, m.height = 0xFFFFFFFF, 0xFFFFFFFF
        m.row_step = 0xFFFFFFFF

    return [
        case("missing_z", "z", drop_z),
        case("unsupported_datatype", "42", bad_type),
        case("unsupported_count", "count", bad_count),
        case("point_step_too_small", "point_step", small_step),
        case("row_step_too_small", "row_step", small_row),
        case("data_length", "data", bad_len),
        case("big_endian", "big", big_endian),
        case("size_overflow", "", overflow),
    ]


def level(status):
    """diagnostic_msgs `byte` fields are bytes in rclpy."""
    return status.level[0] if isinstance(status.level, bytes) else status.level


def test_malformed_clouds_are_reported_and_the_node_keeps_running(spawn, ros):
    from diagnostic_msgs.msg import DiagnosticArray
    from rcl_interfaces.msg import Log
    from sensor_msgs.msg import PointCloud2

    logs, stats = [], []
    ros.node.create_subscription(Log, "/rosout", logs.append, qos("reliable", 1000))
    ros.node.create_subscription(DiagnosticArray, "/cloud_stats", stats.append, qos("reliable", 100))
    pub = ros.node.create_publisher(PointCloud2, "/aerial_cloud", qos("reliable", 100))
    inspector = spawn("cloud_inspector", "--ros-args", "-p", "qos:=reliable")
    # Also wait for the inspector's /cloud_stats writer: a report sent before this reader is
    # matched is not delivered (once in CI, 7 of 8 error reports arrived).
    assert ros.spin_until(lambda: pub.get_subscription_count() > 0
                          and ros.node.count_publishers("/cloud_stats") > 0, 30)
    cases = [p.values for p in malformed_cases()]
    for k, (msg, expect) in enumerate(cases):
        msg.header.stamp.sec = k + 1
        pub.publish(msg)
        errors = lambda: [e for e in logs if e.level >= Log.ERROR and "rejected" in e.msg]  # noqa: E731
        assert ros.spin_until(lambda: len(errors()) > k, 15), f"no error on /rosout for case {k}: {inspector.stderr()}"
        assert expect.lower() in errors()[k].msg.lower(), errors()[k].msg
        assert errors()[k].name == "cloud_inspector"
    good = good_cloud(500)
    good.header.stamp.sec = 99
    pub.publish(good)
    ok = lambda: [s for a in stats for s in a.status if level(s) == 0]  # noqa: E731
    assert ros.spin_until(lambda: len(ok()) >= 1, 15), inspector.stderr()
    values = {kv.key: kv.value for kv in ok()[-1].values}
    assert values["points"] == "500"
    assert inspector.p.poll() is None, "inspector died"
    assert len([s for a in stats for s in a.status if level(s) == 2]) == len(cases)


def test_unreadable_file_is_a_clear_error(spawn, tmp_path):
    bad = tmp_path / "broken.ply"
    bad.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 10\nproperty float x\n"
                    b"property float y\nproperty float z\nend_header\n" + b"\0" * 7)
    p = spawn("cloud_publisher", "--ros-args", "-p", f"file:={bad}", "-p", "linger:=false")
    assert p.p.wait(30) != 0
    err = p.stderr()
    assert str(bad) in err and "truncated" in err.lower(), err


def test_bad_parameters_are_clear_errors(spawn, tmp_path):
    p = spawn("cloud_publisher", "--ros-args", "-p", "synthetic_points:=lots")
    assert p.p.wait(30) != 0
    assert "synthetic_points" in p.stderr() or "invalid type" in p.stderr(), p.stderr()
    params = tmp_path / "p.yaml"
    params.write_text("cloud_publisher:\n  ros__parameters:\n    topik: /x\n")
    p = spawn("cloud_publisher", "--ros-args", "--params-file", str(params))
    assert p.p.wait(30) != 0
    assert "topik" in p.stderr(), p.stderr()


def test_params_file_and_overrides_apply(spawn, ros, tmp_path):
    params = tmp_path / "p.yaml"
    params.write_text("cloud_publisher:\n  ros__parameters:\n    topic: /from_file\n    synthetic_points: 777\n"
                      "    frame_id: survey\n")
    spawn("cloud_publisher", "--ros-args", "--params-file", str(params), "-p", "synthetic_points:=321")
    (tiles,) = receive_clouds(ros, "/from_file", "latched", 1)
    assert tiles[0].width == 321 and tiles[0].header.frame_id == "survey"


def test_use_sim_time_stamps_clouds_with_clock(spawn, ros):
    from rosgraph_msgs.msg import Clock

    clock = ros.node.create_publisher(Clock, "/clock", qos("sensor", 10))
    spawn("cloud_publisher", "--ros-args", "-p", "use_sim_time:=true", "-p", "synthetic_points:=50",
          "-p", "wait_for_subscribers:=1", "-p", "count:=3", "-p", "period_s:=0.3")
    from sensor_msgs.msg import PointCloud2

    got = []
    ros.node.create_subscription(PointCloud2, "/aerial_cloud", got.append, qos("latched", 10))
    end = time.time() + 30
    while time.time() < end and len(got) < 3:
        c = Clock()
        c.clock.sec, c.clock.nanosec = 4242, 0
        clock.publish(c)
        ros.executor.spin_once(timeout_sec=0.05)
    assert len(got) >= 1
    assert got[-1].header.stamp.sec == 4242


def test_sigterm_stops_a_node_cleanly(spawn):
    import signal

    p = spawn("cloud_publisher", "--ros-args", "-p", "synthetic_points:=10")
    time.sleep(2.0)
    assert p.p.poll() is None
    t = time.time()
    assert p.stop(signal.SIGTERM) == 0
    assert time.time() - t < 5.0


def test_localhost_discovery_range_reaches_rclpy(spawn, domain, tmp_path):
    """A LOCALHOST-range Rust publisher (the demo's default) and a stock rclpy
    subscriber find each other. (rclpy itself in LOCALHOST mode receives large
    clouds very slowly: docs/transport.md.)"""
    sink = spawn(str(PEER), "sink", "--topic", "/local", "--qos", "latched", "--count", "1", "--check-synthetic",
                 "--timeout", "60")
    assert sink.json_lines(1, 30)[0] == {"ready": True}
    spawn("cloud_publisher", "--ros-args", "-p", "topic:=/local", "-p", "synthetic_points:=300000",
          "-p", "wait_for_subscribers:=1", extra_env={"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST"})
    lines = sink.json_lines(1, 60)
    assert lines[0]["points"] == 300000 and lines[0]["valid"], sink.stderr()


def test_bad_discovery_range_is_a_clear_error(spawn):
    p = spawn("cloud_publisher", extra_env={"ROS_AUTOMATIC_DISCOVERY_RANGE": "MOON"})
    assert p.p.wait(30) != 0
    assert "ROS_AUTOMATIC_DISCOVERY_RANGE" in p.stderr()
