#!/usr/bin/env python3
"""The rclpy side of skyground's cloud transport, as a plain ROS 2 user writes it.

    peer_cloud.py sink --topic /aerial_cloud --count 1 [--qos latched] [--check-synthetic]
    peer_cloud.py send --topic /aerial_cloud --points 5000000 --count 1

`sink` reassembles skyground's tiled clouds (docs/transport.md): messages with
the same header.stamp are concatenated until one has fewer than TILE_POINTS
points. It prints one JSON line per whole cloud. `send` publishes each cloud as
one PointCloud2 message, as any rclpy node would, and prints its start time.

Large clouds from RustDDS arrive as bursts of UDP datagrams; Fast DDS's default
socket buffer (the OS default, ~208 KiB) overflows. This script raises it the
way any rclpy user can, before rclpy starts:
    FASTDDS_BUILTIN_TRANSPORTS=UDPv4?sockets_size=4194304
"""
import argparse
import json
import math
import os
import sys
import time

os.environ.setdefault("FASTDDS_BUILTIN_TRANSPORTS", "DEFAULT?sockets_size=4194304")

import numpy as np  # noqa: E402
import rclpy  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from sensor_msgs.msg import PointCloud2, PointField  # noqa: E402

TILE_POINTS = 65536


def qos(name, depth):
    durability = DurabilityPolicy.TRANSIENT_LOCAL if name == "latched" else DurabilityPolicy.VOLATILE
    reliability = ReliabilityPolicy.BEST_EFFORT if name == "sensor" else ReliabilityPolicy.RELIABLE
    return QoSProfile(depth=depth, history=HistoryPolicy.KEEP_LAST, reliability=reliability, durability=durability)


def synthetic(n):
    """skyground_core::cloud::synthetic::tilted_plane, in float32 like the Rust code."""
    side = max(1, math.ceil(math.sqrt(n)))
    step = np.float32(100.0) / np.float32(side)
    i = np.arange(n, dtype=np.int64)
    x = (i % side).astype(np.float32) * step
    y = (i // side).astype(np.float32) * step
    z = np.float32(0.05) * x + np.float32(0.02) * y
    label = np.array([2, 5, 6], np.uint8)[i % 3]
    return np.stack([x, y, z], axis=1), label


def to_arrays(msg):
    """x, y, z (float32 or float64) and label of a little-endian PointCloud2."""
    types = {PointField.FLOAT32: np.float32, PointField.FLOAT64: np.float64, PointField.UINT8: np.uint8,
             PointField.UINT32: np.uint32, PointField.INT32: np.int32}
    fields = {f.name: f for f in msg.fields}
    dtype = np.dtype({"names": [f.name for f in msg.fields],
                      "formats": [types[f.datatype] for f in msg.fields],
                      "offsets": [f.offset for f in msg.fields],
                      "itemsize": msg.point_step})
    rec = np.frombuffer(bytes(msg.data), dtype=dtype, count=msg.width * msg.height)
    xyz = np.stack([rec["x"], rec["y"], rec["z"]], axis=1).astype(np.float32)
    label = rec["label"] if "label" in fields else None
    return xyz, label


def sink(args):
    rclpy.init()
    node = Node("peer_cloud_sink")
    groups = {}
    done = []

    def on_msg(msg):
        key = (msg.header.stamp.sec, msg.header.stamp.nanosec)
        groups.setdefault(key, []).append(msg)
        if msg.width == TILE_POINTS and msg.height == 1:
            return
        tiles = groups.pop(key)
        now = time.time_ns()
        xyz, label = zip(*(to_arrays(t) for t in tiles))
        xyz = np.concatenate(xyz)
        label = None if label[0] is None else np.concatenate(label)
        valid = True
        if args.check_synthetic:
            exp_xyz, exp_label = synthetic(len(xyz))
            valid = bool(np.array_equal(xyz, exp_xyz) and label is not None and np.array_equal(label, exp_label))
        out = {"points": int(len(xyz)), "bytes": int(sum(len(t.data) for t in tiles)), "tiles": len(tiles),
               "stamp": list(key), "complete_ns": now, "valid": valid}
        print(json.dumps(out), flush=True)
        done.append(out)

    node.create_subscription(PointCloud2, args.topic, on_msg, qos(args.qos, args.depth))
    print(json.dumps({"ready": True}), flush=True)
    end = time.time() + args.timeout
    while time.time() < end and (args.count == 0 or len(done) < args.count):
        rclpy.spin_once(node, timeout_sec=0.05)
    node.destroy_node()
    rclpy.shutdown()
    return 0 if args.count == 0 or len(done) >= args.count else 1


def send(args):
    rclpy.init()
    node = Node("peer_cloud_send")
    pub = node.create_publisher(PointCloud2, args.topic, qos(args.qos, 1))
    end = time.time() + args.timeout
    while pub.get_subscription_count() == 0 and time.time() < end:
        rclpy.spin_once(node, timeout_sec=0.05)
    if pub.get_subscription_count() == 0:
        print(json.dumps({"error": "no subscriber"}), flush=True)
        return 1
    time.sleep(1.0)
    xyz, label = synthetic(args.points)
    rec = np.zeros(args.points, dtype=np.dtype({"names": ["x", "y", "z", "label"],
                                                "formats": [np.float32] * 3 + [np.uint8],
                                                "offsets": [0, 4, 8, 12], "itemsize": 16}))
    rec["x"], rec["y"], rec["z"], rec["label"] = xyz[:, 0], xyz[:, 1], xyz[:, 2], label
    msg = PointCloud2()
    msg.header.frame_id = "map"
    msg.height, msg.width = 1, args.points
    msg.fields = [PointField(name=n, offset=o, datatype=t, count=1) for n, o, t in
                  [("x", 0, PointField.FLOAT32), ("y", 4, PointField.FLOAT32), ("z", 8, PointField.FLOAT32),
                   ("label", 12, PointField.UINT8)]]
    msg.point_step, msg.row_step, msg.is_dense = 16, 16 * args.points, True
    msg.data = rec.tobytes()
    for k in range(args.count):
        msg.header.stamp.sec, msg.header.stamp.nanosec = 1000 + k, 0
        start = time.time_ns()
        pub.publish(msg)
        print(json.dumps({"stamp": [1000 + k, 0], "start_ns": start, "bytes": len(msg.data)}), flush=True)
        t = time.time() + args.gap
        while time.time() < t:
            rclpy.spin_once(node, timeout_sec=0.05)
    t = time.time() + args.linger
    while time.time() < t:
        rclpy.spin_once(node, timeout_sec=0.05)
    node.destroy_node()
    rclpy.shutdown()
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("mode", choices=["sink", "send"])
    p.add_argument("--topic", default="/aerial_cloud")
    p.add_argument("--count", type=int, default=1)
    p.add_argument("--points", type=int, default=100000)
    p.add_argument("--qos", default="reliable", choices=["latched", "reliable", "sensor"])
    p.add_argument("--depth", type=int, default=256)
    p.add_argument("--timeout", type=float, default=120.0)
    p.add_argument("--gap", type=float, default=1.0)
    p.add_argument("--linger", type=float, default=5.0)
    p.add_argument("--check-synthetic", action="store_true")
    args = p.parse_args()
    return sink(args) if args.mode == "sink" else send(args)


if __name__ == "__main__":
    sys.exit(main())
