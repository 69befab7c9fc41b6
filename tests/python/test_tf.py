"""vehicle_sim's tf tree in a bag (issue 16 part 4): `/tf` (map → base_link,
with each odometry) and `/tf_static` (base_link → sensor, latched) as
tf2_msgs/msg/TFMessage, recorded by `skyground record` as the demo does, decode
with mcap-ros2-support from the bag's own schema (tf2_msgs has no rclpy wheel
on PyPI, so the bag is the check) and agree with /state_estimation."""
import math
import signal
import warnings

from test_vehicle_sim import sim, way_point  # noqa: F401 (fixture)

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from mcap_ros2.reader import read_ros2_messages


def test_tf_in_the_bag_decodes_and_follows_the_vehicle(sim, spawn, ros, tmp_path):  # noqa: F811
    _, odom = sim
    bag = tmp_path / "tf.mcap"
    rec = spawn("skyground", "record", "-o", bag, "/tf:tf2_msgs/msg/TFMessage",
                "/tf_static:tf2_msgs/msg/TFMessage", "/state_estimation:nav_msgs/msg/Odometry")
    assert ros.spin_until(lambda: "recording" in rec.stderr() or len(odom) > 200, 30)
    way_point(ros, 20.0, 5.0)
    ros.spin_until(lambda: False, 4.0)
    assert rec.stop(signal.SIGINT) == 0, rec.stderr()

    by_topic = {}
    for m in read_ros2_messages(str(bag)):
        by_topic.setdefault(m.channel.topic, []).append(m)
    assert by_topic.get("/tf") and by_topic.get("/tf_static"), {k: len(v) for k, v in by_topic.items()}
    assert by_topic["/tf"][0].schema.name == "tf2_msgs/msg/TFMessage"

    static = by_topic["/tf_static"][0].ros_msg.transforms[0]
    assert (static.header.frame_id, static.child_frame_id) == ("base_link", "sensor")
    assert abs(static.transform.translation.z - 1.8) < 1e-6  # vehicle.sensor_height

    tfs = [m.ros_msg.transforms[0] for m in by_topic["/tf"]]
    assert all((t.header.frame_id, t.child_frame_id) == ("map", "base_link") for t in tfs)
    xs = [t.transform.translation.x for t in tfs]
    assert max(xs) - min(xs) > 2.0, "the vehicle drove towards x = 20"
    # Each /tf is its odometry's pose: same stamp, same position, same yaw.
    odoms = {(m.ros_msg.header.stamp.sec, m.ros_msg.header.stamp.nanosec): m.ros_msg.pose.pose
             for m in by_topic.get("/state_estimation", [])}
    matched = 0
    for t in tfs:
        pose = odoms.get((t.header.stamp.sec, t.header.stamp.nanosec))
        if pose is None:
            continue
        matched += 1
        assert abs(pose.position.x - t.transform.translation.x) < 1e-9
        q = t.transform.rotation
        yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
        assert abs(yaw - math.atan2(2 * pose.orientation.w * pose.orientation.z,
                                    1 - 2 * pose.orientation.z ** 2)) < 1e-6
    assert matched >= 10, matched
