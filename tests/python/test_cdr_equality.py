"""CDR of the Rust message structs equals rclpy's, type by type.

The Rust side prints one JSON line per sample message:
``{"type": "pkg/msg/Type", "fields": {...}, "cdr_hex": "..."}``. For each line
this test builds the same message with rclpy, serializes it with
``rclpy.serialization.serialize_message`` and compares the bytes; then it
deserializes the Rust bytes with rclpy and compares the field values.

Padding: rclpy (Fast CDR) leaves CDR alignment padding bytes uninitialised,
so they hold whatever was in memory. The test computes where the padding is
(from the message's type layout) and zeroes those bytes in rclpy's output
before comparing; the Rust side always writes zero padding, so the comparison
is exact everywhere else and the lengths must match.

Run: ``/tmp/probe/venv/bin/python -m pytest tests/python/test_cdr_equality.py -q``
from the repository root. The sample printer is ``$SKYGROUND_SAMPLES_CMD``
(split with shlex) when set, else
``cargo run -q -p skyground-msgs --example cdr_samples``.
No DDS traffic is involved.
"""

import functools
import importlib
import json
import os
import shlex
import subprocess
from pathlib import Path

import pytest
from rclpy.serialization import deserialize_message, serialize_message
from rosidl_parser import definition as idl

REPO_ROOT = Path(__file__).resolve().parents[2]
DEFAULT_CMD = "cargo run -q -p skyground-msgs --example cdr_samples"
MIN_TYPES = 20
# Types the project publishes or reads; each must have a sample.
REQUIRED_TYPES = {
    "builtin_interfaces/msg/Time",
    "std_msgs/msg/Header",
    "sensor_msgs/msg/PointCloud2",
    "geometry_msgs/msg/PointStamped",
    "geometry_msgs/msg/PoseStamped",
    "nav_msgs/msg/Path",
    "nav_msgs/msg/Odometry",
    "visualization_msgs/msg/Marker",
    "visualization_msgs/msg/MarkerArray",
    "diagnostic_msgs/msg/DiagnosticArray",
    "rosgraph_msgs/msg/Clock",
    "rcl_interfaces/msg/Log",
}

# Sizes of CDR primitives by IDL type name.
PRIMITIVE_SIZE = {
    "boolean": 1, "octet": 1, "char": 1, "wchar": 2,
    "int8": 1, "uint8": 1, "int16": 2, "uint16": 2,
    "int32": 4, "uint32": 4, "int64": 8, "uint64": 8,
    "float": 4, "double": 8, "long double": 8,
}
ENCAPSULATION = 4


@functools.lru_cache(maxsize=None)
def samples():
    """Runs the sample printer once; returns its parsed lines."""
    env_cmd = os.environ.get("SKYGROUND_SAMPLES_CMD")
    argv = shlex.split(env_cmd if env_cmd else DEFAULT_CMD)
    proc = subprocess.run(
        argv, cwd=REPO_ROOT, capture_output=True, text=True, timeout=1800
    )
    if proc.returncode != 0:
        raise RuntimeError(
            f"sample printer {argv} failed ({proc.returncode}):\n{proc.stderr}"
        )
    return [json.loads(line) for line in proc.stdout.splitlines() if line.strip()]


# Packages with no wheel on PyPI (`pip index versions ros-kilted-tf2-msgs`: none):
# their types are checked by decoding the bag's schema with mcap-ros2-support
# instead (test_bag_format.py).
NO_WHEEL = {"tf2_msgs"}


def message_class(type_name):
    """``pkg/msg/Type`` → the rclpy message class."""
    package, kind, name = type_name.split("/")
    if package in NO_WHEEL:
        pytest.skip(f"{package}: no rclpy package on PyPI to compare with")
    return getattr(importlib.import_module(f"{package}.{kind}"), name)


def namespaced_class(slot_type):
    """The message class of a NamespacedType slot."""
    module = importlib.import_module(".".join(slot_type.namespaces))
    return getattr(module, slot_type.name)


def fields_of(msg_or_class):
    """(field name, slot type) pairs in .msg order."""
    names = msg_or_class.get_fields_and_field_types().keys()
    return list(zip(names, msg_or_class.SLOT_TYPES))


# --- filling an rclpy message from JSON ------------------------------------


def fill(cls, fields):
    """A ``cls`` instance with every field set from the JSON object ``fields``."""
    expected = [name for name, _ in fields_of(cls)]
    assert sorted(fields) == sorted(expected), (
        f"{cls.__name__}: JSON keys {sorted(fields)} != .msg fields {sorted(expected)}"
    )
    msg = cls()
    for name, slot_type in fields_of(cls):
        setattr(msg, name, convert(slot_type, fields[name]))
    return msg


def convert(slot_type, value):
    """A JSON value → what the rclpy setter of ``slot_type`` accepts."""
    if isinstance(slot_type, idl.NamespacedType):
        return fill(namespaced_class(slot_type), value)
    if isinstance(slot_type, idl.AbstractNestedType):
        inner = slot_type.value_type
        if isinstance(inner, idl.BasicType) and inner.typename in ("uint8", "octet"):
            return bytes(value) if inner.typename == "octet" else list(value)
        return [convert(inner, v) for v in value]
    if isinstance(slot_type, idl.AbstractGenericString):
        return str(value)
    if isinstance(slot_type, idl.BasicType):
        t = slot_type.typename
        if t == "octet":
            return bytes([value])
        if t == "boolean":
            return bool(value)
        if t in ("char", "wchar"):
            return chr(value) if isinstance(value, int) else value
        if t in ("float", "double", "long double"):
            return float(value)
        return int(value)
    raise TypeError(f"unhandled slot type {slot_type!r}")


# --- rclpy message → plain JSON-like values ---------------------------------


def plain(slot_type, value):
    """An rclpy field value → the JSON form the Rust side prints."""
    if isinstance(slot_type, idl.NamespacedType):
        return {name: plain(t, getattr(value, name)) for name, t in fields_of(value)}
    if isinstance(slot_type, idl.AbstractNestedType):
        return [plain(slot_type.value_type, v) for v in value]
    if isinstance(slot_type, idl.BasicType):
        t = slot_type.typename
        if t == "octet":
            return value[0] if isinstance(value, bytes) else int(value)
        if t == "boolean":
            return bool(value)
        if t in ("float", "double", "long double"):
            return float(value)
        if t in ("char", "wchar"):
            return value
        return int(value)
    return value


def plain_message(msg):
    """All fields of an rclpy message as nested dicts and lists."""
    return {name: plain(t, getattr(msg, name)) for name, t in fields_of(msg)}


# --- where CDR puts padding -------------------------------------------------


class PaddingWalker:
    """Walks a message in CDR order, recording the offsets of padding bytes.

    Offsets are into the serialized buffer (encapsulation header included);
    alignment is relative to the end of the header, as in ROS 2.
    """

    def __init__(self):
        self.pos = 0
        self.padding = []

    def align(self, size):
        while self.pos % size:
            self.padding.append(ENCAPSULATION + self.pos)
            self.pos += 1

    def primitive(self, size):
        self.align(size)
        self.pos += size

    def message(self, msg):
        for name, slot_type in fields_of(msg):
            self.value(slot_type, getattr(msg, name))

    def value(self, slot_type, value):
        if isinstance(slot_type, idl.NamespacedType):
            self.message(value)
        elif isinstance(slot_type, idl.AbstractNestedType):
            if isinstance(slot_type, idl.AbstractSequence):
                self.primitive(4)
            for v in value:
                self.value(slot_type.value_type, v)
        elif isinstance(slot_type, idl.AbstractString):
            self.primitive(4)
            self.pos += len(value.encode("utf-8")) + 1
        elif isinstance(slot_type, idl.BasicType):
            self.primitive(PRIMITIVE_SIZE[slot_type.typename])
        else:
            raise TypeError(f"unhandled slot type {slot_type!r}")


def zero_padding(serialized, msg):
    """rclpy's bytes with CDR padding zeroed; checks the layout length too."""
    walker = PaddingWalker()
    walker.message(msg)
    assert ENCAPSULATION + walker.pos == len(serialized), (
        f"layout walk ends at {ENCAPSULATION + walker.pos}, rclpy wrote {len(serialized)} bytes"
    )
    out = bytearray(serialized)
    for offset in walker.padding:
        out[offset] = 0
    return bytes(out)


# --- the tests --------------------------------------------------------------


def sample_ids():
    return [s["type"] for s in samples()]


@pytest.fixture(scope="module")
def by_type():
    return {s["type"]: s for s in samples()}


def test_every_type_is_sampled_once():
    types = sample_ids()
    assert len(types) == len(set(types)), f"duplicate samples: {types}"
    assert len(types) >= MIN_TYPES, f"only {len(types)} types sampled"
    missing = REQUIRED_TYPES - set(types)
    assert not missing, f"no sample for {sorted(missing)}"
    for line in samples():
        assert set(line) == {"type", "fields", "cdr_hex"}, line.keys()


@pytest.mark.parametrize("type_name", sample_ids())
def test_rust_cdr_equals_rclpy(type_name, by_type):
    sample = by_type[type_name]
    cls = message_class(type_name)
    msg = fill(cls, sample["fields"])
    rust = bytes.fromhex(sample["cdr_hex"])
    ours = serialize_message(msg)
    assert rust[:ENCAPSULATION] == b"\x00\x01\x00\x00", rust[:ENCAPSULATION].hex()
    assert len(rust) == len(ours), f"Rust {len(rust)} bytes, rclpy {len(ours)} bytes"
    assert zero_padding(ours, msg).hex() == sample["cdr_hex"]


@pytest.mark.parametrize("type_name", sample_ids())
def test_rclpy_reads_rust_cdr(type_name, by_type):
    sample = by_type[type_name]
    cls = message_class(type_name)
    back = deserialize_message(bytes.fromhex(sample["cdr_hex"]), cls)
    assert plain_message(back) == sample["fields"]
    assert plain_message(back) == plain_message(fill(cls, sample["fields"]))


def test_padding_walker_on_empty_pointcloud2():
    from sensor_msgs.msg import PointCloud2

    msg = PointCloud2()
    walker = PaddingWalker()
    walker.message(msg)
    # frame_id "" (4 + 1 bytes) then 3 padding; is_bigendian then 3 padding.
    assert walker.padding == [17, 18, 19, 33, 34, 35]
    assert ENCAPSULATION + walker.pos == len(serialize_message(msg)) == 49


def test_convert_handles_bytes_and_fixed_arrays():
    from diagnostic_msgs.msg import DiagnosticStatus
    from geometry_msgs.msg import PoseWithCovariance

    status = fill(
        DiagnosticStatus,
        {"level": 2, "name": "n", "message": "m", "hardware_id": "h", "values": []},
    )
    assert status.level == DiagnosticStatus.ERROR
    pose = fill(
        PoseWithCovariance,
        {
            "pose": plain_message(PoseWithCovariance().pose),
            "covariance": [float(i) for i in range(36)],
        },
    )
    assert list(pose.covariance) == [float(i) for i in range(36)]
    assert plain_message(pose)["covariance"][35] == 35.0
