"""`skyground play`: a bag recorded by `skyground record` comes back over DDS
to rclpy with its contents, its QoS (latched topics reach late joiners) and
its timing."""
import signal
import time

from conftest import qos, record_live_bag


def test_played_bag_reaches_rclpy_with_timing(spawn, ros, tmp_path):
    from nav_msgs.msg import Odometry, Path
    from sensor_msgs.msg import PointCloud2

    bag = tmp_path / "for_play.mcap"
    source = record_live_bag(ros, spawn, bag, 100000, [(0, i) for i in range(5)], range(6), 0.4)
    # Only the player may publish from here on.
    source.stop()

    got = {"odom": [], "path": [], "tiles": []}
    ros.node.create_subscription(
        Odometry, "/state_estimation", lambda m: got["odom"].append((time.time(), m.pose.pose.position.x)), qos("reliable", 50)
    )
    ros.node.create_subscription(Path, "/global_path", lambda m: got["path"].append(m), qos("latched", 1))
    ros.node.create_subscription(PointCloud2, "/aerial_cloud", lambda m: got["tiles"].append(m.width), qos("latched", 16))
    play = spawn("skyground", "play", bag, "--rate", "2", "--delay", "4", "--linger")
    assert ros.spin_until(lambda: len(got["odom"]) == 6 and got["path"] and sum(got["tiles"]) == 100000, 60), (
        (len(got["odom"]), len(got["path"]), got["tiles"]),
        play.stderr(),
    )
    assert [x for _, x in got["odom"]] == [float(k) for k in range(6)]
    assert [p.pose.position.y for p in got["path"][0].poses] == [float(i) for i in range(5)]
    # Recorded 0.4 s apart, played at rate 2: 5 gaps of ~0.2 s.
    span = got["odom"][-1][0] - got["odom"][0][0]
    assert 0.6 < span < 2.5, span
    assert play.stop(signal.SIGINT) == 0, play.stderr()
