#!/usr/bin/env python3
"""A robot played by rclpy for `skyground demo --field`, with the CMU
exploration environment's interface, as a real robot's driver would speak it:

    field_robot.py --gt gt_samples.ply --start X Y [--speed 5] [--range 30]

It subscribes to /way_point (geometry_msgs/PointStamped) and drives straight
at it at --speed (poses stepped at 10 Hz; it ignores obstacles: the
way-points are ground-graph poses a few metres apart), publishing
/state_estimation (nav_msgs/Odometry, map → base_link) every step and
/registered_scan (sensor_msgs/PointCloud2 x, y, z float32 in the map frame)
whenever it has moved 1 m or every second.

Its scans are real geometry: the scene's ground-truth building surface samples
(`skyground aerial --out DIR` writes DIR/gt_samples.ply), filtered as a
VLP-16-like sensor 1.8 m above the ground would see them:
- range: within --range metres of the sensor;
- height: within the beams' ±15° elevation;
- line of sight, roughly: per 1° azimuth × 2° elevation cell only the points
  within 0.5 m of the cell's nearest one (a z-buffer: the far side of a
  building and walls behind walls are hidden).

No /tf: tf2_msgs has no wheel on PyPI (`pip index versions
ros-kilted-tf2-msgs`), so rclpy here cannot publish it. Prints one JSON line
per event on stdout ("ready", "way_point", "arrived").
"""
import argparse
import json
import math
import os
import time

os.environ.setdefault("FASTDDS_BUILTIN_TRANSPORTS", "DEFAULT?sockets_size=4194304")

import numpy as np  # noqa: E402
import rclpy  # noqa: E402
import rclpy.executors  # noqa: E402
from geometry_msgs.msg import PointStamped  # noqa: E402
from nav_msgs.msg import Odometry  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from sensor_msgs.msg import PointCloud2, PointField  # noqa: E402

SENSOR_HEIGHT = 1.8
HALF_FOV = math.radians(15.0)
STEP_S = 0.1


def read_gt(path):
    """x, y, z of skyground's gt_samples.ply (binary little endian)."""
    data = open(path, "rb").read()
    head, body = data.split(b"end_header\n", 1)
    props = [line.split()[1:] for line in head.decode().splitlines() if line.startswith("property")]
    kinds = {"float": "<f4", "double": "<f8", "uchar": "u1", "uint": "<u4", "int": "<i4"}
    dtype = np.dtype([(name, kinds[kind]) for kind, name in props])
    v = np.frombuffer(body, dtype=dtype)
    return np.stack([v["x"], v["y"], v["z"]], axis=1).astype(np.float32)


def visible(points, sensor, max_range):
    """The points a spinning LiDAR at `sensor` sees: range, beam elevation, z-buffer."""
    d = points - sensor
    r = np.linalg.norm(d, axis=1)
    elev = np.arcsin(np.clip(d[:, 2] / np.maximum(r, 1e-6), -1.0, 1.0))
    keep = (r < max_range) & (r > 0.5) & (np.abs(elev) <= HALF_FOV)
    d, r, elev = d[keep], r[keep], elev[keep]
    pts = points[keep]
    if len(pts) == 0:
        return pts
    az = np.degrees(np.arctan2(d[:, 1], d[:, 0])).astype(np.int32) + 180
    el = (np.degrees(elev) / 2.0).astype(np.int32) + 10
    cell = az * 100 + el
    nearest = np.full(cell.max() + 1, np.inf, dtype=np.float32)
    np.minimum.at(nearest, cell, r)
    return pts[r <= nearest[cell] + 0.5]


def cloud_msg(stamp, pts):
    m = PointCloud2()
    m.header.stamp = stamp
    m.header.frame_id = "map"
    m.height, m.width = 1, len(pts)
    m.fields = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                for i, n in enumerate("xyz")]
    m.is_bigendian, m.point_step, m.row_step, m.is_dense = False, 12, 12 * len(pts), True
    m.data = np.ascontiguousarray(pts, dtype=np.float32).tobytes()
    return m


def say(**kv):
    print(json.dumps(kv), flush=True)


class Robot(Node):
    def __init__(self, args):
        super().__init__("field_robot")
        self.gt = read_gt(args.gt)
        self.pos = np.array([args.start[0], args.start[1], 0.0])
        self.yaw = 0.0
        self.speed, self.range = args.speed, args.range
        self.goal = None
        self.last_scan = (None, 0.0)
        reliable = QoSProfile(depth=10, history=HistoryPolicy.KEEP_LAST,
                              reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
        sensor = QoSProfile(depth=5, history=HistoryPolicy.KEEP_LAST,
                            reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.VOLATILE)
        self.odom_pub = self.create_publisher(Odometry, "/state_estimation", reliable)
        self.scan_pub = self.create_publisher(PointCloud2, "/registered_scan", sensor)
        self.create_subscription(PointStamped, "/way_point", self.on_way_point, reliable)
        self.create_timer(STEP_S, self.step)
        self.driven = 0.0
        say(event="ready", points=len(self.gt))

    def on_way_point(self, m):
        goal = np.array([m.point.x, m.point.y, m.point.z])
        if self.goal is None or np.linalg.norm(goal[:2] - self.goal[:2]) > 1e-3:
            say(event="way_point", x=m.point.x, y=m.point.y)
        self.goal = goal

    def step(self):
        if self.goal is not None:
            d = self.goal[:2] - self.pos[:2]
            dist = float(np.linalg.norm(d))
            move = min(dist, self.speed * STEP_S)
            if dist > 1e-6:
                self.yaw = math.atan2(d[1], d[0])
                self.pos[:2] += d / dist * move
                self.pos[2] = self.goal[2]
                self.driven += move
        stamp = self.get_clock().now().to_msg()
        o = Odometry()
        o.header.stamp, o.header.frame_id, o.child_frame_id = stamp, "map", "base_link"
        o.pose.pose.position.x, o.pose.pose.position.y, o.pose.pose.position.z = map(float, self.pos)
        o.pose.pose.orientation.z, o.pose.pose.orientation.w = math.sin(self.yaw / 2), math.cos(self.yaw / 2)
        self.odom_pub.publish(o)
        where, when = self.last_scan
        now = time.monotonic()
        if where is None or np.linalg.norm(self.pos - where) >= 1.0 or now - when >= 1.0:
            self.last_scan = (self.pos.copy(), now)
            sensor = (self.pos + [0.0, 0.0, SENSOR_HEIGHT]).astype(np.float32)
            self.scan_pub.publish(cloud_msg(stamp, visible(self.gt, sensor, self.range)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gt", required=True)
    ap.add_argument("--start", nargs=2, type=float, required=True)
    ap.add_argument("--speed", type=float, default=5.0)
    ap.add_argument("--range", type=float, default=30.0)
    args = ap.parse_args()
    rclpy.init()
    node = Robot(args)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass
    finally:
        say(event="stopped", driven_m=round(node.driven, 1))
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
