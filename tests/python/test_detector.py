"""completeness_detector and target_generator over DDS with rclpy: a classified
cloud of two box buildings (one with its east wall left out) and a building of
a few points goes in; missing points, per-building completeness, markers and
targets come out, with one building id across every topic."""
import json
import math

import numpy as np
import pytest

from conftest import qos

TILE_POINTS = 65536
_TYPES = {1: np.int8, 2: np.uint8, 3: np.int16, 4: np.uint16, 5: np.int32, 6: np.uint32, 7: np.float32,
          8: np.float64}
_CODES = {np.dtype(t): c for c, t in _TYPES.items()}


# --- clouds as a plain rclpy user sends and receives them (docs/transport.md) ---

def cloud_msg(columns, stamp_sec=1, frame_id="map"):
    """One PointCloud2 from named numpy columns (x, y, z first), little endian, packed."""
    from sensor_msgs.msg import PointCloud2, PointField

    n = len(columns["x"])
    names, formats, offsets, off = [], [], [], 0
    for name, col in columns.items():
        dt = np.dtype(col.dtype)
        off = (off + dt.itemsize - 1) // dt.itemsize * dt.itemsize
        names.append(name), formats.append(dt), offsets.append(off)
        off += dt.itemsize
    step = (off + 3) // 4 * 4
    rec = np.zeros(n, dtype=np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": step}))
    for name, col in columns.items():
        rec[name] = col
    m = PointCloud2()
    m.header.frame_id = frame_id
    m.header.stamp.sec = stamp_sec
    m.height, m.width = 1, n
    m.fields = [PointField(name=nm, offset=o, datatype=_CODES[f], count=1) for nm, f, o in zip(names, formats, offsets)]
    m.point_step, m.row_step, m.is_dense, m.is_bigendian = step, step * n, True, False
    m.data = rec.tobytes()
    return m


def columns_of(msgs):
    """Every field of a reassembled cloud (a list of tiles) as numpy columns."""
    fields = msgs[0].fields
    dtype = np.dtype({"names": [f.name for f in fields], "formats": [_TYPES[f.datatype] for f in fields],
                      "offsets": [f.offset for f in fields], "itemsize": msgs[0].point_step})
    recs = [np.frombuffer(bytes(m.data), dtype=dtype, count=m.width * m.height) for m in msgs]
    rec = np.concatenate(recs) if recs else np.zeros(0, dtype)
    return {f.name: np.array(rec[f.name]) for f in fields}


class Clouds:
    """Subscribes to a cloud topic and reassembles skyground's tiles: messages
    with one stamp until one holds fewer than TILE_POINTS points."""

    def __init__(self, ros, topic, kind="latched", depth=300):
        from sensor_msgs.msg import PointCloud2

        self.topic, self.groups, self.done = topic, {}, []
        ros.node.create_subscription(PointCloud2, topic, self._on, qos(kind, depth))

    def _on(self, m):
        key = (m.header.stamp.sec, m.header.stamp.nanosec)
        self.groups.setdefault(key, []).append(m)
        if m.width * m.height != TILE_POINTS:
            tiles = self.groups.pop(key)
            self.done.append((tiles[0].header, columns_of(tiles)))

    def last(self):
        return self.done[-1][1]


class Latest:
    """The messages of a (latched) topic, as they come."""

    def __init__(self, ros, msg_type, topic, kind="latched", depth=10):
        self.msgs = []
        ros.node.create_subscription(msg_type, topic, self.msgs.append, qos(kind, depth))

    def last(self):
        return self.msgs[-1]


def level(status):
    """diagnostic_msgs `byte` fields are bytes in rclpy."""
    return status.level[0] if isinstance(status.level, bytes) else status.level


def values(status):
    return {kv.key: kv.value for kv in status.values}


def logs_of(logs, name, min_level):
    return [e for e in logs if e.name == name and e.level >= min_level]


# --- the scene ---

# (id, x0, y0, x1, y1, height, walls left out)
BOX1 = (1, 15.0, 15.0, 35.0, 30.0, 9.0, ())
BOX2 = (2, 55.0, 15.0, 75.0, 35.0, 8.0, ("east",))
TINY = (3, 88.0, 50.0, 89.5, 51.5)  # 30 points: too few to outline
LEFT_OUT_WALL = ((75.0, 15.0), (75.0, 35.0))


def grid(a0, a1, b0, b1, step):
    a = np.arange(a0, a1 + 1e-6, step)
    b = np.arange(b0, b1 + 1e-6, step)
    aa, bb = np.meshgrid(a, b)
    return aa.ravel(), bb.ravel()


def box_points(x0, y0, x1, y1, h, left_out=(), rng=None):
    """Roof and walls of a box at 0.25 m, 1 cm noise."""
    rng = rng or np.random.default_rng(1)
    pts = []
    x, y = grid(x0, x1, y0, y1, 0.25)
    pts.append(np.stack([x, y, np.full_like(x, h)], axis=1))
    walls = {"south": ((x0, y0), (x1, y0)), "north": ((x0, y1), (x1, y1)),
             "west": ((x0, y0), (x0, y1)), "east": ((x1, y0), (x1, y1))}
    for name, ((ax, ay), (bx, by)) in walls.items():
        if name in left_out:
            continue
        length = math.hypot(bx - ax, by - ay)
        t, z = grid(0.0, length, 0.0, h - 0.25, 0.25)
        f = t / length
        pts.append(np.stack([ax + f * (bx - ax), ay + f * (by - ay), z], axis=1))
    p = np.concatenate(pts)
    return p + rng.normal(0.0, 0.01, p.shape)


def scene():
    """x, y, z, label and true building id of the test scene."""
    rng = np.random.default_rng(7)
    gx, gy = grid(0.0, 100.0, 0.0, 60.0, 0.5)
    under = np.zeros(len(gx), bool)
    for _, x0, y0, x1, y1, *_ in (BOX1, BOX2):
        under |= (gx > x0) & (gx < x1) & (gy > y0) & (gy < y1)
    ground = np.stack([gx[~under], gy[~under], rng.normal(0.0, 0.01, (~under).sum())], axis=1)
    parts = [(ground, 2, 0)]
    for bid, x0, y0, x1, y1, h, left_out in (BOX1, BOX2):
        parts.append((box_points(x0, y0, x1, y1, h, left_out, rng), 6, bid))
    bid, x0, y0, x1, y1 = TINY
    tiny = np.stack([rng.uniform(x0, x1, 30), rng.uniform(y0, y1, 30), rng.uniform(0.5, 3.0, 30)], axis=1)
    parts.append((tiny, 6, bid))
    xyz = np.concatenate([p for p, _, _ in parts]).astype(np.float32)
    label = np.concatenate([np.full(len(p), c, np.uint8) for p, c, _ in parts])
    building = np.concatenate([np.full(len(p), b, np.uint32) for p, _, b in parts])
    return xyz, label, building


def footprints_geojson(path, extra=()):
    def square(x0, y0, x1, y1, pad=0.0):
        return [[[x0 - pad, y0 - pad], [x1 + pad, y0 - pad], [x1 + pad, y1 + pad], [x0 - pad, y1 + pad],
                 [x0 - pad, y0 - pad]]]

    feats = [{"type": "Feature", "id": b[0], "properties": {"name": f"box {b[0]}"},
              "geometry": {"type": "Polygon", "coordinates": square(*b[1:5])}} for b in (BOX1, BOX2)]
    feats.append({"type": "Feature", "id": TINY[0], "properties": {"name": "tiny"},
                  "geometry": {"type": "Polygon", "coordinates": square(*TINY[1:5], pad=0.25)}})
    feats.extend(extra)
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}))
    return path


def dist_to_segment(xy, seg):
    (ax, ay), (bx, by) = seg
    d = np.array([bx - ax, by - ay])
    t = np.clip(((xy - [ax, ay]) @ d) / (d @ d), 0.0, 1.0)
    return np.linalg.norm(xy - ([ax, ay] + t[:, None] * d), axis=1)


# --- running the nodes ---

class Outputs:
    """Every output of the detector (and the generator), subscribed before the nodes start."""

    def __init__(self, ros):
        from diagnostic_msgs.msg import DiagnosticArray
        from rcl_interfaces.msg import Log
        from visualization_msgs.msg import MarkerArray

        self.ros = ros
        self.missing = Clouds(ros, "/missing_points")
        self.targets = Clouds(ros, "/target_points")
        self.completeness = Latest(ros, DiagnosticArray, "/completeness")
        self.markers = Latest(ros, MarkerArray, "/detection_markers")
        self.regions = Latest(ros, MarkerArray, "/target_regions")
        self.logs = []
        ros.node.create_subscription(Log, "/rosout", self.logs.append, qos("reliable", 1000))

    def detection(self):
        return self.missing.done and self.completeness.msgs and self.markers.msgs

    def statuses(self):
        return {int(values(s)["building"]): s for s in self.completeness.last().status}


def publish_classified(ros, xyz, label, building=None, subscribers=1, stamp_sec=1):
    from sensor_msgs.msg import PointCloud2

    pub = ros.node.create_publisher(PointCloud2, "/classified_cloud", qos("latched", 1))
    assert ros.spin_until(lambda: pub.get_subscription_count() >= subscribers, 30), "nodes never subscribed"
    cols = {"x": xyz[:, 0], "y": xyz[:, 1], "z": xyz[:, 2], "label": label}
    if building is not None:
        cols["building"] = building
    pub.publish(cloud_msg(cols, stamp_sec))
    return pub


def stderr_of(*procs):
    return "\n".join(f"--- {p.args[0]}:\n{p.stderr()[-3000:]}" for p in procs)


@pytest.fixture
def scene_cloud():
    return scene()


def test_detector_and_generator_agree_on_building_ids_and_find_the_missing_wall(spawn, ros, tmp_path,
                                                                                  scene_cloud):
    xyz, label, _ = scene_cloud
    fp = footprints_geojson(tmp_path / "footprints.geojson")
    out = Outputs(ros)
    det = spawn("completeness_detector", "--ros-args", "-p", f"footprints:={fp}")
    gen = spawn("target_generator")
    publish_classified(ros, xyz, label, subscribers=2)
    assert ros.spin_until(out.detection, 60), stderr_of(det)
    assert ros.spin_until(lambda: out.targets.done and out.regions.msgs, 60), stderr_of(det, gen)

    # /completeness: one status per footprint; the tiny one skipped with a WARN.
    st = out.statuses()
    assert sorted(st) == [1, 2, 3], [s.name for s in out.completeness.last().status]
    for bid, s in st.items():
        assert s.name == f"building {bid}"
    tiny = st[3]
    assert level(tiny) == 1 and tiny.message.startswith("skipped:"), (level(tiny), tiny.message)
    assert int(values(tiny)["points"]) == 30
    ok = {b: values(s) for b, s in st.items() if level(s) == 0}
    assert sorted(ok) == [1, 2], {b: s.message for b, s in st.items()}
    # One wall of four equal sides is a quarter of the outline; the closed box misses nearly nothing.
    assert 0.15 <= float(ok[2]["r_missing"]) <= 0.4, ok[2]
    assert float(ok[1]["r_missing"]) < 0.08, ok[1]
    for v in ok.values():
        assert abs(float(v["completeness"]) + float(v["r_missing"]) - 1.0) < 1e-6
        assert v["strategy"] in ("point", "region")
    assert det.p.poll() is None, stderr_of(det)

    # /missing_points: per building as many as /completeness says, near the left-out wall.
    miss = out.missing.last()
    assert set(miss) >= {"x", "y", "z", "building"}
    mb = miss["building"]
    for b, v in ok.items():
        assert (mb == b).sum() == int(v["missing"]), (b, v)
    assert set(np.unique(mb)) <= {1, 2}
    assert (mb == 2).sum() >= 20
    mxy = np.stack([miss["x"], miss["y"]], axis=1).astype(np.float64)
    near = dist_to_segment(mxy, LEFT_OUT_WALL) < 1.5
    assert near.mean() >= 0.85, f"{near.mean():.2f} of {len(mb)} missing points near the left-out wall"
    assert (miss["z"][mb == 2] > 0).all() and (miss["z"][mb == 2] < BOX2[5]).all()
    # Each point's outward normal and skeleton point ride along as standard FLOAT32 fields:
    # unit normals pointing from the skeleton point through the missing point.
    assert set(miss) >= {"nx", "ny", "sx", "sy"}, sorted(miss)
    n = np.stack([miss["nx"], miss["ny"]], axis=1).astype(np.float64)
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-3)
    ray = mxy - np.stack([miss["sx"], miss["sy"]], axis=1)
    assert ((ray * n).sum(axis=1) > 0).all()

    # /detection_markers: contours for the outlined buildings only, missing/ID as big as /missing_points.
    from visualization_msgs.msg import Marker

    markers = out.markers.last().markers
    assert markers[0].action == Marker.DELETEALL
    by_ns = {}
    for m in markers[1:]:
        kind, _, bid = m.ns.partition("/")
        by_ns.setdefault(kind, {}).setdefault(int(bid), []).append(m)
    assert sorted(by_ns.get("contour", {})) == [1, 2], list(by_ns)
    assert sorted(by_ns.get("skeleton", {})) == [1, 2]
    assert sorted(by_ns.get("missing", {})) == sorted(b for b, v in ok.items() if int(v["missing"]) > 0)
    for b, ms in by_ns["missing"].items():
        assert sum(len(m.points) for m in ms) == (mb == b).sum()
    for b in (1, 2):
        pts = np.array([[p.x, p.y] for m in by_ns["contour"][b] for p in m.points])
        x0, y0, x1, y1 = (BOX1, BOX2)[b - 1][1:5]
        assert np.abs(pts.min(0) - [x0, y0]).max() < 1.0 and np.abs(pts.max(0) - [x1, y1]).max() < 1.0, pts

    # /target_points and /target_regions: only for buildings with missing walls, by their strategy.
    tp = out.targets.last()
    tb = tp["building"]
    regions = [m for m in out.regions.last().markers if m.action == Marker.ADD]
    assert out.regions.last().markers[0].action == Marker.DELETEALL
    rb = {int(m.ns) for m in regions}
    with_missing = {b for b, v in ok.items() if int(v["missing"]) > 0}
    assert 2 in set(np.unique(tb).tolist()) | rb and set(np.unique(tb).tolist()) | rb <= with_missing, \
        f"targets of {np.unique(tb)}, regions of {rb}\n{stderr_of(gen)}"
    for b in np.unique(tb):
        assert ok[int(b)]["strategy"] == "point"
    for b in rb:
        assert ok[b]["strategy"] == "region"
    # Box 2's targets stand on open ground east of its missing wall, a few metres off.
    if ok[2]["strategy"] == "point":
        t2 = np.stack([tp["x"][tb == 2], tp["y"][tb == 2]], axis=1).astype(np.float64)
        assert len(t2) >= 1
        d = dist_to_segment(t2, LEFT_OUT_WALL)
        assert (t2[:, 0] > 75.0).all() and (d > 2.0).all() and (d < 20.0).all(), t2
    else:
        pts = np.array([[p.x, p.y] for m in regions if int(m.ns) == 2 for p in m.points])
        assert len(pts) >= 3 and (dist_to_segment(pts, LEFT_OUT_WALL) < 20.0).all(), pts
    assert gen.p.poll() is None and det.p.poll() is None, stderr_of(det, gen)


def test_derived_footprints_give_the_same_picture(spawn, ros, scene_cloud):
    """Without a footprint file the detector outlines the buildings itself; the
    30-point cluster is either dropped or reported as skipped, never a crash."""
    xyz, label, _ = scene_cloud
    out = Outputs(ros)
    det = spawn("completeness_detector")
    publish_classified(ros, xyz, label)
    assert ros.spin_until(out.detection, 60), stderr_of(det)
    st = out.statuses()
    ok = {b: values(s) for b, s in st.items() if level(s) == 0}
    assert len(ok) == 2, {b: (level(s), s.message) for b, s in st.items()}
    for b, s in st.items():
        if level(s) != 0:
            assert level(s) == 1 and s.message.startswith("skipped:") and int(values(s)["points"]) < 50, s.message
    miss = out.missing.last()
    mb = miss["building"]
    assert set(np.unique(mb)) <= set(ok)
    for b, v in ok.items():
        assert (mb == b).sum() == int(v["missing"])
    # The building whose missing points these are is box 2, whatever id it got.
    mxy = np.stack([miss["x"], miss["y"]], axis=1).astype(np.float64)
    near = dist_to_segment(mxy, LEFT_OUT_WALL) < 1.5
    assert len(mb) >= 20 and near.mean() >= 0.85, f"{near.mean():.2f} of {len(mb)} near the left-out wall"
    b2 = int(np.bincount(mb).argmax())
    assert 0.15 <= float(ok[b2]["r_missing"]) <= 0.4, ok
    other = [b for b in ok if b != b2]
    assert float(ok[other[0]]["r_missing"]) < 0.08, ok
    ids = {int(m.ns.partition("/")[2]) for m in out.markers.last().markers[1:]}
    assert ids == set(ok), (ids, set(ok))
    assert det.p.poll() is None, stderr_of(det)


def test_degenerate_footprint_is_reported_and_detection_goes_on(spawn, ros, tmp_path, scene_cloud):
    from rcl_interfaces.msg import Log

    xyz, label, _ = scene_cloud
    flat = {"type": "Feature", "id": 4, "properties": {"name": "flat"},
            "geometry": {"type": "Polygon", "coordinates": [[[40.0, 45.0], [45.0, 45.0], [50.0, 45.0],
                                                             [40.0, 45.0]]]}}
    fp = footprints_geojson(tmp_path / "degenerate.geojson", extra=[flat])
    out = Outputs(ros)
    det = spawn("completeness_detector", "--ros-args", "-p", f"footprints:={fp}")
    publish_classified(ros, xyz, label)
    assert ros.spin_until(out.detection, 60), stderr_of(det)

    def reported():
        in_log = [e.msg for e in logs_of(out.logs, "completeness_detector", Log.WARN) if "footprint" in e.msg.lower()]
        in_status = [s.message for s in out.completeness.last().status
                     if values(s).get("building") == "4" and level(s) >= 1]
        return in_log + in_status

    assert ros.spin_until(lambda: reported(), 10), stderr_of(det)
    assert any("degenerate" in r or "area" in r.lower() or str(fp) in r for r in reported()), reported()
    st = out.statuses()
    assert [b for b, s in st.items() if level(s) == 0] == [1, 2], {b: s.message for b, s in st.items()}
    assert 4 not in st or level(st[4]) == 1, st[4].message

    # Still running: a second cloud (box 2 now whole) is detected again, with less missing.
    full = np.concatenate([xyz, box_points(*BOX2[1:6]).astype(np.float32)])
    before = float(values(st[2])["r_missing"])
    n = len(out.completeness.msgs)
    publish_classified(ros, full, np.concatenate([label, np.full(len(full) - len(xyz), 6, np.uint8)]), stamp_sec=2)
    assert ros.spin_until(lambda: len(out.completeness.msgs) > n, 60), stderr_of(det)
    after = float(values(out.statuses()[2])["r_missing"])
    assert after < before and after < 0.08, (before, after)
    assert det.p.poll() is None, stderr_of(det)


def test_cloud_without_labels_is_an_error_not_a_crash(spawn, ros, scene_cloud):
    from rcl_interfaces.msg import Log

    xyz, label, _ = scene_cloud
    out = Outputs(ros)
    det = spawn("completeness_detector")
    from sensor_msgs.msg import PointCloud2

    pub = ros.node.create_publisher(PointCloud2, "/classified_cloud", qos("latched", 1))
    assert ros.spin_until(lambda: pub.get_subscription_count() >= 1, 30)
    pub.publish(cloud_msg({"x": xyz[:, 0], "y": xyz[:, 1], "z": xyz[:, 2]}, 1))
    errors = lambda: [e.msg for e in logs_of(out.logs, "completeness_detector", Log.ERROR)]  # noqa: E731
    assert ros.spin_until(lambda: any("label" in m for m in errors()), 30), stderr_of(det)
    assert not out.completeness.msgs
    pub.publish(cloud_msg({"x": xyz[:, 0], "y": xyz[:, 1], "z": xyz[:, 2], "label": label}, 2))
    assert ros.spin_until(out.detection, 60), stderr_of(det)
    assert det.p.poll() is None


def test_footprint_ids_ride_on_completeness(spawn, ros, tmp_path, scene_cloud):
    """Each footprint's own id (here BAG `identificatie`) is on its /completeness status."""
    xyz, label, _ = scene_cloud
    fp = footprints_geojson(tmp_path / "bag.geojson")
    doc = json.loads(fp.read_text())
    for f in doc["features"]:
        f["properties"]["identificatie"] = f"05031000000{f['id']:05d}"
    fp.write_text(json.dumps(doc))
    out = Outputs(ros)
    det = spawn("completeness_detector", "--ros-args", "-p", f"footprints:={fp}")
    publish_classified(ros, xyz, label)
    assert ros.spin_until(out.detection, 60), stderr_of(det)
    for bid, s in out.statuses().items():
        assert values(s)["footprint_id"] == f"05031000000{bid:05d}", values(s)


def _fails_at_start(proc, timeout=30):
    try:
        proc.p.wait(timeout)
    except Exception:  # noqa: BLE001 - still running is the failure
        pass
    return proc.p.poll()


@pytest.mark.parametrize("case", ["missing", "not_json", "crs"])
def test_footprints_that_cannot_be_used_stop_the_node_at_start(spawn, tmp_path, case):
    """No silent fall-back to derived footprints: the node exits non-zero with the reason."""
    params = []
    if case == "missing":
        fp, want = tmp_path / "nope.geojson", ["nope.geojson", "No such file"]
    elif case == "not_json":
        fp = tmp_path / "broken.geojson"
        fp.write_text('{"type": "FeatureCollection", "features": [')
        want = ["broken.geojson", "invalid JSON"]
    else:
        fp = footprints_geojson(tmp_path / "rd.geojson")
        doc = json.loads(fp.read_text())
        doc["crs"] = {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::28992"}}
        fp.write_text(json.dumps(doc))
        params = ["-p", "crs:=EPSG:2056"]
        want = ["EPSG:28992", "EPSG:2056"]
    det = spawn("completeness_detector", "--ros-args", "-p", f"footprints:={fp}", *params, respawns=0)
    rc = _fails_at_start(det)
    assert rc is not None and rc != 0, f"still running or exit 0 ({rc})\n{stderr_of(det)}"
    err = det.stderr()
    for w in want:
        assert w in err, err[-2000:]
    assert "deriving them instead" not in err
