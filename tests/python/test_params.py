"""Node parameters as ROS 2 users reach them (issue 16 part 4): rclpy's
parameter client (what `ros2 param list/get/set` calls) lists, gets and sets
the parameters a skyground node declared from its params files through
ros2-client's parameter services. Sets of an unknown name, of another type, or
of a parameter the node reads once at start-up are refused with a reason; a
live one (robot_bridge's follow.*) takes effect at the next message."""
import time

from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry, Path
from diagnostic_msgs.msg import DiagnosticArray
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient

from conftest import qos


def call(ros, future, timeout=20.0):
    assert ros.spin_until(future.done, timeout), "no answer from the parameter service"
    return future.result()


def test_rclpy_lists_gets_and_sets_a_node_parameter(ros, spawn):
    spawn("skyground", "node", "robot_bridge")
    client = AsyncParameterClient(ros.node, "robot_bridge")
    assert client.wait_for_services(timeout_sec=30.0), "robot_bridge's parameter services not found"

    names = call(ros, client.list_parameters()).result.names
    assert {"frame_id", "path_topics", "follow.stall_timeout_s", "resend_period_s", "use_sim_time"} <= set(names), names

    got = call(ros, client.get_parameters(["follow.stall_timeout_s", "path_topics", "frame_id"])).values
    assert got[0].double_value == 30.0  # config/robot_bridge.yaml
    assert list(got[1].string_array_value) == ["/local_path"]
    assert got[2].string_value == "map"

    ok = call(ros, client.set_parameters([Parameter("follow.stall_timeout_s", value=2.0)])).results[0]
    assert ok.successful, ok.reason
    assert call(ros, client.get_parameters(["follow.stall_timeout_s"])).values[0].double_value == 2.0

    refused = call(ros, client.set_parameters([
        Parameter("follow.stall_timeout_s", value="fast"),
        Parameter("colour", value=1),
        Parameter("frame_id", value="odom"),
    ])).results
    assert not refused[0].successful and "type" in refused[0].reason, refused[0].reason
    assert not refused[1].successful and "undeclared" in refused[1].reason, refused[1].reason
    assert not refused[2].successful and "read once at start-up" in refused[2].reason, refused[2].reason
    assert call(ros, client.get_parameters(["frame_id"])).values[0].string_value == "map"

    # The set took effect: a robot that gets no closer for 2 s of its stamps
    # (not the file's 30 s) is reported blocked.
    status = []
    ros.node.create_subscription(DiagnosticArray, "/vehicle_status", status.append, qos("reliable"))
    leg_pub = ros.node.create_publisher(Path, "/local_path", qos("reliable"))
    odom_pub = ros.node.create_publisher(Odometry, "/state_estimation", qos("reliable"))
    assert ros.spin_until(lambda: ros.node.count_subscribers("/local_path") >= 1
                          and ros.node.count_subscribers("/state_estimation") >= 1
                          and ros.node.count_publishers("/vehicle_status") >= 1, 30.0)
    time.sleep(1.0)

    def odom(t):
        o = Odometry()
        o.header.frame_id = "map"
        o.header.stamp.sec = t
        odom_pub.publish(o)

    odom(100)
    ros.spin_until(lambda: False, 0.5)
    leg = Path()
    leg.header.frame_id = "map"
    pose = PoseStamped()
    pose.pose.position.x = 20.0
    leg.poses = [pose]
    leg_pub.publish(leg)
    ros.spin_until(lambda: False, 0.5)
    for t in range(101, 108):
        odom(t)
        if ros.spin_until(lambda: bool(status), 0.3):
            break
    assert status, "no /vehicle_status after 7 s of odometry without progress"
    s = status[0].status[0]
    assert s.message.startswith("blocked") and "for 2 s" in s.message, s.message


def test_use_sim_time_set_while_running_switches_the_stamps_to_clock(ros, spawn):
    """`ros2 param set /cloud_publisher use_sim_time true` on a running node:
    its next clouds carry /clock's time, not the system clock's."""
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import PointCloud2

    clock = ros.node.create_publisher(Clock, "/clock", qos("sensor", 10))
    spawn("cloud_publisher", "--ros-args", "-p", "synthetic_points:=50", "-p", "count:=200", "-p", "period_s:=0.2")
    got = []
    ros.node.create_subscription(PointCloud2, "/aerial_cloud", got.append, qos("latched", 10))
    assert ros.spin_until(lambda: bool(got), 30.0), "no cloud from cloud_publisher"
    assert got[0].header.stamp.sec > 1_000_000_000, "system time before the set"

    client = AsyncParameterClient(ros.node, "cloud_publisher")
    assert client.wait_for_services(timeout_sec=30.0)
    ok = call(ros, client.set_parameters([Parameter("use_sim_time", value=True)])).results[0]
    assert ok.successful, ok.reason
    assert call(ros, client.get_parameters(["use_sim_time"])).values[0].bool_value

    def ticked():
        c = Clock()
        c.clock.sec, c.clock.nanosec = 4242, 0
        clock.publish(c)
        return bool(got) and got[-1].header.stamp.sec == 4242

    assert ros.spin_until(ticked, 30.0), [m.header.stamp.sec for m in got[-5:]]
