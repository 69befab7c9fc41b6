"""`skyground record` over DDS: a bag of live topics that Python's mcap and
rosbags tools decode, valid after SIGINT."""
import signal
import time

import numpy as np
from mcap_ros2.reader import read_ros2_messages

from conftest import qos, record_live_bag


def test_recorded_bag_decodes_in_python(spawn, ros, tmp_path):
    bag = tmp_path / "live.mcap"
    record_live_bag(ros, spawn, bag, 200000, [(i, 0) for i in range(7)], [10.0 + k for k in range(5)], 0.05)

    by_topic = {}
    for m in read_ros2_messages(str(bag)):
        by_topic.setdefault(m.channel.topic, []).append(m.ros_msg)
    assert sorted(by_topic) == ["/aerial_cloud", "/global_path", "/state_estimation"], rec.stderr()
    tiles = by_topic["/aerial_cloud"]
    assert sum(t.width for t in tiles) == 200000 and len(tiles) == 200000 // 65536 + 1
    assert [p.pose.position.x for p in by_topic["/global_path"][0].poses] == [float(i) for i in range(7)]
    assert [o.pose.pose.position.x for o in by_topic["/state_estimation"]] == [10.0 + k for k in range(5)]

    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    with AnyReader([bag], default_typestore=get_typestore(Stores.ROS2_KILTED)) as reader:
        decoded = [(c.topic, reader.deserialize(raw, c.msgtype)) for c, _, raw in reader.messages()]
    assert len(decoded) == sum(len(v) for v in by_topic.values())
    cloud = [m for t, m in decoded if t == "/aerial_cloud"]
    data = np.concatenate([np.frombuffer(bytes(m.data), np.uint8) for m in cloud])
    assert len(data) == 200000 * cloud[0].point_step


def test_sigint_before_any_message_leaves_a_valid_bag(spawn, tmp_path):
    bag = tmp_path / "empty.mcap"
    rec = spawn("skyground", "record", "-o", bag, "/nothing:nav_msgs/msg/Path")
    time.sleep(1.5)
    assert rec.stop(signal.SIGINT) == 0, rec.stderr()
    assert list(read_ros2_messages(str(bag))) == []


def test_every_keeps_one_message_in_n_of_a_best_effort_stream(spawn, ros, tmp_path):
    """--every thins a dense sensor stream; a best-effort (sensor QoS) writer is
    recorded at all, which a reliable reader would never match."""
    from nav_msgs.msg import Odometry

    bag = tmp_path / "every.mcap"
    pub = ros.node.create_publisher(Odometry, "/state_estimation", qos("sensor", 10))
    rec = spawn("skyground", "record", "-o", bag, "/state_estimation:nav_msgs/msg/Odometry",
                "--every", "/state_estimation=3")
    assert ros.spin_until(lambda: pub.get_subscription_count() > 0, 30), rec.stderr()
    ros.spin_until(lambda: False, 0.5)
    for k in range(10):
        o = Odometry()
        o.pose.pose.position.x = float(k)
        pub.publish(o)
        ros.spin_until(lambda: False, 0.05)
    ros.spin_until(lambda: False, 1.0)
    assert rec.stop(signal.SIGINT) == 0, rec.stderr()
    xs = [m.ros_msg.pose.pose.position.x for m in read_ros2_messages(str(bag))]
    assert xs == [0.0, 3.0, 6.0, 9.0], xs


def test_every_rejects_a_bad_count(spawn, tmp_path):
    rec = spawn("skyground", "record", "-o", tmp_path / "x.mcap", "/a", "--every", "/a=0")
    assert rec.p.wait(10) != 0
    assert "N must be a whole number" in rec.stderr()


def test_a_recorder_stuck_creating_a_subscription_closes_its_bag_and_exits_75(spawn, ros, tmp_path):
    """RustDDS 0.15.1 can deadlock a node creating a reader (docs/design.md); the
    recorder then exits with 75 for a respawn, and the bag it leaves is whole:
    summary written, every message it had received kept."""
    from geometry_msgs.msg import PoseStamped
    from mcap.reader import make_reader
    from nav_msgs.msg import Odometry, Path as NavPath

    from conftest import EXIT_STUCK

    bag = tmp_path / "stuck.mcap"
    path_pub = ros.node.create_publisher(NavPath, "/global_path", qos("latched", 1))
    path = NavPath()
    path.header.frame_id = "map"
    for x in range(5):
        p = PoseStamped()
        p.pose.position.x = float(x)
        path.poses.append(p)
    path_pub.publish(path)
    rec = spawn("skyground", "record", "-o", bag, "/global_path", "/state_estimation", respawns=0,
                extra_env={"SKYGROUND_STALL_CREATION": "subscription to /state_estimation",
                           "SKYGROUND_CREATE_LIMIT_S": "2"})
    assert ros.spin_until(lambda: "recording /global_path" in rec.stderr(), 30), rec.stderr()
    ros.spin_until(lambda: False, 1.0)
    # The recorder discovers this publisher and hangs creating its reader.
    ros.node.create_publisher(Odometry, "/state_estimation", qos("reliable", 10))
    assert ros.spin_until(lambda: rec.p.poll() is not None, 40), rec.stderr()
    log = rec.stderr()
    assert rec.p.returncode == EXIT_STUCK, log
    assert "creating subscription to /state_estimation has not returned in 2 s" in log, log
    assert "bag closed before exiting" in log, log
    with open(bag, "rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None and summary.statistics is not None, "the bag has no summary"
    assert summary.statistics.message_count == 1
    msgs = list(read_ros2_messages(str(bag)))
    assert [m.channel.topic for m in msgs] == ["/global_path"]
    assert [p.pose.position.x for p in msgs[0].ros_msg.poses] == [0.0, 1.0, 2.0, 3.0, 4.0]

