"""The Rust MCAP bag writer's files decode with the Python MCAP and rosbags readers.

``nodes/examples/sample_bag.rs`` writes one bag holding sample ``i`` of
``skyground_msgs::samples::all()`` on topic ``/sample/<pkg>/<Type>`` at log time
``BASE_NS + i * STEP_NS`` (publish time 1 µs earlier). This test decodes every
message of that bag twice, with ``mcap_ros2.reader.read_ros2_messages`` and with
``rosbags.highlevel.AnyReader`` opened on the bare ``.mcap`` file (both build their
decoders from the bag's own ``ros2msg`` schemas), and compares the raw bytes, the
times and every decoded field value with the sample printer's JSON.

Run: ``/tmp/probe/venv/bin/python -m pytest tests/python/test_bag_format.py -q``
from the repository root. The bag writer is ``$SKYGROUND_SAMPLE_BAG_CMD`` (split
with shlex, output path appended) when set, else
``cargo run -q -p skyground-nodes --example sample_bag --``; the sample printer is
``$SKYGROUND_SAMPLES_CMD`` when set, else
``cargo run -q -p skyground-msgs --example cdr_samples``.
"""

import functools
import json
import math
import os
import shlex
import subprocess
import warnings
from pathlib import Path

import pytest
from mcap.reader import make_reader
from rosbags.highlevel import AnyReader
from rosbags.interfaces import QosDurability, QosReliability

# mcap_ros2.reader warns on import that it is deprecated in favour of
# DecoderFactory; read_ros2_messages still works and is the API under test.
with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from mcap_ros2.reader import read_ros2_messages

REPO_ROOT = Path(__file__).resolve().parents[2]
DEFAULT_BAG_CMD = "cargo run -q -p skyground-nodes --example sample_bag --"
DEFAULT_SAMPLES_CMD = "cargo run -q -p skyground-msgs --example cdr_samples"
BASE_NS = 1_700_000_000_000_000_000
STEP_NS = 1_000_000
PUBLISH_LAG_NS = 1_000
# Build plus run of a cold workspace can take long on two cores.
TIMEOUT_S = 1800


def run(env_var, default, extra=()):
    """Runs the command of ``$env_var`` (or ``default``) with ``extra`` args; returns stdout."""
    env_cmd = os.environ.get(env_var)
    argv = shlex.split(env_cmd if env_cmd else default) + list(extra)
    proc = subprocess.run(
        argv, cwd=REPO_ROOT, capture_output=True, text=True, timeout=TIMEOUT_S
    )
    if proc.returncode != 0:
        raise RuntimeError(f"{argv} failed ({proc.returncode}):\n{proc.stderr}")
    return proc.stdout


@functools.lru_cache(maxsize=None)
def samples():
    """Sample lines of the printer, in order: ``[{"type", "fields", "cdr_hex"}, ...]``."""
    out = run("SKYGROUND_SAMPLES_CMD", DEFAULT_SAMPLES_CMD)
    return [json.loads(line) for line in out.splitlines() if line.strip()]


def expected():
    """Per type: (index in the bag, fields, cdr bytes)."""
    return {
        s["type"]: (i, s["fields"], bytes.fromhex(s["cdr_hex"]))
        for i, s in enumerate(samples())
    }


def topic_of(type_name):
    """``pkg/msg/Type`` → ``/sample/pkg/Type``, as the example names topics."""
    package, _, name = type_name.split("/")
    return f"/sample/{package}/{name}"


@pytest.fixture(scope="module")
def bag(tmp_path_factory):
    """Path of the bag the Rust example wrote."""
    path = tmp_path_factory.mktemp("bag") / "samples.mcap"
    run("SKYGROUND_SAMPLE_BAG_CMD", DEFAULT_BAG_CMD, [str(path)])
    assert path.is_file(), f"the example wrote no {path}"
    return path


def assert_fields(decoded, want, where):
    """Checks a decoded message (any reader's objects) against the sample's JSON fields."""
    if isinstance(want, dict):
        for key, value in want.items():
            assert hasattr(decoded, key), f"{where}: no field {key}"
            assert_fields(getattr(decoded, key), value, f"{where}.{key}")
    elif isinstance(want, list):
        got = list(decoded)  # list, bytes or numpy array
        assert len(got) == len(want), f"{where}: {len(got)} elements, want {len(want)}"
        for i, (g, w) in enumerate(zip(got, want)):
            assert_fields(g, w, f"{where}[{i}]")
    elif isinstance(want, bool):
        assert bool(decoded) is want, f"{where}: {decoded!r} != {want!r}"
    elif isinstance(want, int):
        assert int(decoded) == want, f"{where}: {decoded!r} != {want!r}"
    elif isinstance(want, float):
        # float32 fields print with f32's shortest form; compare at f32 precision.
        assert math.isclose(float(decoded), want, rel_tol=1e-6, abs_tol=1e-30), (
            f"{where}: {decoded!r} != {want!r}"
        )
    else:
        assert decoded == want, f"{where}: {decoded!r} != {want!r}"


def mcap_ros2_messages(bag):
    """``{type: (topic, log_time, publish_time, decoded)}`` via mcap_ros2."""
    out = {}
    with open(bag, "rb") as f:
        for m in read_ros2_messages(f):
            assert m.schema.name not in out, f"{m.schema.name} twice"
            out[m.schema.name] = (
                m.channel.topic,
                m.log_time_ns,
                m.publish_time_ns,
                m.ros_msg,
            )
    return out


def rosbags_messages(bag):
    """``{type: (topic, log_time, raw, decoded, connection)}`` via rosbags' AnyReader."""
    out = {}
    with AnyReader([bag]) as reader:
        for connection, timestamp, raw in reader.messages():
            decoded = reader.deserialize(raw, connection.msgtype)
            assert connection.msgtype not in out, f"{connection.msgtype} twice"
            out[connection.msgtype] = (
                connection.topic,
                timestamp,
                bytes(raw),
                decoded,
                connection,
            )
    return out


def test_file_layout_is_rosbag2(bag):
    with open(bag, "rb") as f:
        reader = make_reader(f)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        raw = {
            schema.name: (channel.topic, bytes(message.data))
            for schema, channel, message in reader.iter_messages()
        }
    assert summary is not None, "no summary section"
    assert summary.statistics.message_count == len(samples())
    assert len(summary.schemas) == len(samples()), "one schema per type"
    assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
    assert {s.name for s in summary.schemas.values()} == set(expected())
    assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
    for channel in summary.channels.values():
        assert "offered_qos_profiles" in channel.metadata, channel.topic
    assert summary.chunk_indexes, "messages are not chunked"
    assert {c.compression for c in summary.chunk_indexes} == {"zstd"}
    assert raw == {t: (topic_of(t), cdr) for t, (_, _, cdr) in expected().items()}


def test_mcap_ros2_decodes_every_message(bag):
    got = mcap_ros2_messages(bag)
    want = expected()
    assert set(got) == set(want)
    for type_name, (index, fields, _) in want.items():
        topic, log_time, publish_time, decoded = got[type_name]
        assert topic == topic_of(type_name)
        assert log_time == BASE_NS + index * STEP_NS, type_name
        assert publish_time == log_time - PUBLISH_LAG_NS, type_name
        assert_fields(decoded, fields, type_name)


def test_rosbags_decodes_every_message(bag):
    got = rosbags_messages(bag)
    want = expected()
    assert set(got) == set(want)
    for type_name, (index, fields, cdr) in want.items():
        topic, timestamp, raw, decoded, connection = got[type_name]
        assert topic == topic_of(type_name)
        assert timestamp == BASE_NS + index * STEP_NS, type_name
        assert raw == cdr, type_name
        assert_fields(decoded, fields, type_name)
        assert connection.ext.serialization_format == "cdr"
        (qos,) = connection.ext.offered_qos_profiles
        assert qos.reliability == QosReliability.RELIABLE
        assert qos.durability == QosDurability.VOLATILE
        assert qos.depth == 10


@pytest.mark.parametrize("reader", ["mcap_ros2", "rosbags"])
def test_selected_fields(bag, reader):
    """Spot checks written out by hand, independent of the JSON comparison."""
    if reader == "mcap_ros2":
        decoded = {t: v[3] for t, v in mcap_ros2_messages(bag).items()}
    else:
        decoded = {t: v[3] for t, v in rosbags_messages(bag).items()}

    cloud = decoded["sensor_msgs/msg/PointCloud2"]
    assert (cloud.height, cloud.width, cloud.point_step, cloud.row_step) == (1, 2, 13, 26)
    assert [(f.name, f.offset, f.datatype) for f in cloud.fields] == [
        ("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("label", 12, 2)
    ]
    assert bytes(bytearray(cloud.data)) == bytes(range(1, 27))
    assert cloud.header.frame_id == "map"
    assert cloud.is_dense is True and cloud.is_bigendian is False

    path = decoded["nav_msgs/msg/Path"]
    assert [p.pose.position.x for p in path.poses] == [1.0, 2.0, 3.0]
    assert {p.header.frame_id for p in path.poses} == {"odom_1"}

    marker = decoded["visualization_msgs/msg/Marker"]
    assert [(p.x, p.y, p.z) for p in marker.points] == [
        (1.0, -2.5, 0.125), (2.0, -2.5, 0.125), (3.0, -2.5, 0.125)
    ]
    assert marker.text == "Geb\u00e4ude \u2713"
    assert bytes(bytearray(marker.mesh_file.data)) == bytes([1, 2, 3, 250, 255])

    log = decoded["rcl_interfaces/msg/Log"]
    assert (log.msg, log.line) == ("building 3: 41% seen", 1234)
