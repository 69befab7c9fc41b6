"""Region exploration end to end (issue 6): the reference scene's aerial prior
with its ground-truth labels as /classified_cloud → completeness_detector →
target_generator → global_planner → local_explorer ↔ vehicle_sim. The vehicle
starts beside a region; the explorer takes it, scans its missing walls, and
hands it back "done" with the coverage risen."""
import time

import numpy as np

from conftest import qos
from test_classifier import prior  # noqa: F401  (the reference prior, made once per module)
from test_detector import Clouds, Latest, cloud_msg, level, values

GROUND, BUILDING = 2, 6
TAU = 0.25  # the completeness radius, as the explorer's tau_m


def inside(poly, pts):
    """Even-odd rule for many points."""
    x, y = pts[:, 0], pts[:, 1]
    result = np.zeros(len(pts), bool)
    n = len(poly)
    for i in range(n):
        (ax, ay), (bx, by) = poly[i], poly[(i + 1) % n]
        crosses = (ay > y) != (by > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = ax + (y - ay) * (bx - ax) / (by - ay)
        result ^= crosses & (x < xc)
    return result


def dist_to_polygon(poly, pts):
    d = np.full(len(pts), np.inf)
    n = len(poly)
    for i in range(n):
        a, b = np.asarray(poly[i]), np.asarray(poly[(i + 1) % n])
        ab = b - a
        t = np.clip(((pts - a) @ ab) / max(ab @ ab, 1e-12), 0.0, 1.0)
        d = np.minimum(d, np.linalg.norm(pts - (a + t[:, None] * ab), axis=1))
    d[inside(poly, pts)] = 0.0
    return d


def covered(samples, cloud, tau=TAU):
    """Which samples have a point of `cloud` within tau (3D), by a tau grid."""
    out = np.zeros(len(samples), bool)
    if len(cloud) == 0 or len(samples) == 0:
        return out
    lo = samples.min(0) - 2 * tau
    hi = samples.max(0) + 2 * tau
    c = cloud[np.all((cloud >= lo) & (cloud <= hi), axis=1)]
    cells = {}
    for k, key in enumerate(map(tuple, np.floor(c / tau).astype(np.int64))):
        cells.setdefault(key, []).append(k)
    for i, s in enumerate(samples):
        key = np.floor(s / tau).astype(np.int64)
        idx = [k for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
               for k in cells.get((key[0] + dx, key[1] + dy, key[2] + dz), ())]
        if idx and np.min(np.linalg.norm(c[idx] - s, axis=1)) <= tau:
            out[i] = True
    return out


def start_in(poly, xyz, label):
    """A ground point inside the region polygon with nothing but ground within 2 m."""
    poly = np.asarray(poly)
    lo, hi = poly.min(0) - 3.0, poly.max(0) + 3.0
    box = np.all((xyz[:, :2] >= lo) & (xyz[:, :2] <= hi), axis=1)
    pts, lab = xyz[box], label[box]
    ground = pts[(lab == GROUND) & inside(poly, pts[:, :2])]
    others = pts[lab != GROUND][:, :2]
    centre = poly.mean(0)
    for g in ground[np.argsort(np.linalg.norm(ground[:, :2] - centre, axis=1))][::7]:
        if len(others) == 0 or np.min(np.linalg.norm(others - g[:2], axis=1)) > 2.0:
            return float(g[0]), float(g[1])
    return None


def test_region_is_explored_and_its_coverage_rises(spawn, ros, prior):
    from diagnostic_msgs.msg import DiagnosticArray
    from sensor_msgs.msg import PointCloud2
    from visualization_msgs.msg import Marker, MarkerArray

    xyz, label = prior
    t_start = time.time()
    missing = Clouds(ros, "/missing_points")
    resampled = Clouds(ros, "/resampled_cloud")
    completeness = Latest(ros, DiagnosticArray, "/completeness")
    regions = Latest(ros, MarkerArray, "/target_regions")
    active = Latest(ros, MarkerArray, "/active_region")
    explorer = Latest(ros, DiagnosticArray, "/explorer_status", depth=100)
    planner = Latest(ros, DiagnosticArray, "/planner_status", depth=100)
    pub = ros.node.create_publisher(PointCloud2, "/classified_cloud", qos("latched", 1))
    # Everyone who reads the 31 MB prior subscribes before it is published.
    procs = [spawn("completeness_detector"), spawn("target_generator"), spawn("local_explorer", "--ros-args", "-p", "publish_each_region:=true"),
             spawn("global_planner")]

    def logs():
        return "\n".join(f"--- {p.args[0]}:\n{p.stderr()[-2500:]}" for p in procs)

    # Discovery under CI load has twice taken over 30 s in this test; on failure, name who is missing.
    assert ros.spin_until(lambda: pub.get_subscription_count() >= 4, 90), \
        (f"/classified_cloud matched {pub.get_subscription_count()} of 4 readers: "
         f"{[i.node_name for i in ros.node.get_subscriptions_info_by_topic('/classified_cloud')]}; "
         f"graph {ros.node.get_node_names()}\n{logs()}")
    pub.publish(cloud_msg({"x": xyz[:, 0], "y": xyz[:, 1], "z": xyz[:, 2], "label": label}, 1))
    assert ros.spin_until(lambda: missing.done and completeness.msgs and regions.msgs, 120), logs()
    status = {int(values(s)["building"]): values(s) for s in completeness.last().status if level(s) == 0}
    region_markers = [m for m in regions.last().markers if m.action == Marker.ADD and m.type == Marker.LINE_STRIP]
    print(f"{len(status)} buildings, {sum(1 for v in status.values() if v['strategy'] == 'region')} region-based, "
          f"{len(region_markers)} regions, {len(missing.last()['x'])} missing points "
          f"({time.time() - t_start:.0f} s)")
    print("\n".join(line for line in procs[1].stderr().splitlines() if "round" in line))
    assert region_markers, f"no regions from the reference prior: {status}"
    for m in region_markers:
        assert status[int(m.ns)]["strategy"] == "region", (m.ns, status.get(int(m.ns)))

    # Start the vehicle inside the region with the most missing wall next to it.
    miss = missing.last()
    mxyz = np.stack([miss["x"], miss["y"], miss["z"]], axis=1).astype(np.float64)

    def surface(m):
        poly = [(p.x, p.y) for p in m.points[:-1]]
        sel = (miss["building"] == int(m.ns)) & (dist_to_polygon(poly, mxyz[:, :2]) <= 3.0)
        return poly, mxyz[sel]

    chosen = None
    for m in sorted(region_markers, key=lambda m: -len(surface(m)[1])):
        poly, _ = surface(m)
        start = start_in(poly, xyz, label)
        if start:
            chosen = (m, start)
            break
    assert chosen, "no free ground inside any region to start from"
    start = chosen[1]
    print(f"start at ({start[0]:.1f}, {start[1]:.1f}) in region {chosen[0].ns}/{chosen[0].id}")

    procs.append(spawn("vehicle_sim", "--ros-args", "-p", "scene:=reference", "-p",
                       f"start:=[{start[0]:.2f}, {start[1]:.2f}]", "-p", "time_factor:=20.0"))

    def states():
        return [(s.message, values(s)) for a in explorer.msgs for s in a.status]

    def done():
        return [v for msg, v in states() if msg == "done"]

    assert ros.spin_until(lambda: done() or any(s.message == "done" for a in planner.msgs for s in a.status),
                          max(30.0, 175.0 - (time.time() - t_start))), \
        f"no region done; explorer {states()[-3:]}; planner {[values(s) for s in planner.last().status] if planner.msgs else None}\n{logs()}"
    assert done(), f"the planner finished without exploring a region\n{logs()}"
    finished = done()[0]
    region, rnd = finished["region"], finished["round"]
    exploring = [v for msg, v in states() if msg == "exploring" and v["region"] == region and v["round"] == rnd]
    assert exploring, f"region {region} was never reported exploring: {states()[:5]}"
    before, after = float(exploring[0]["coverage"]), float(finished["coverage"])

    # The region the planner handed over: /planner_status names its index, building and round,
    # /active_region carries its polygon (ns = the building).
    named = [values(s) for a in planner.msgs for s in a.status
             if values(s).get("active_region") == region and values(s).get("round") == rnd]
    assert named, f"/planner_status never named region {region} of round {rnd}"
    handed = [m for a in active.msgs for m in a.markers if m.action == Marker.ADD
              and m.type == Marker.LINE_STRIP and m.ns == named[0]["active_building"]]
    assert handed, [(m.ns, m.id) for a in active.msgs for m in a.markers]
    poly, samples = surface(handed[0])

    # Independent look: the region's missing wall samples near a point of the aerial prior, then
    # of the prior plus what the vehicle scanned (/resampled_cloud, published when the region ended).
    assert ros.spin_until(lambda: resampled.done, 30), logs()
    rs = resampled.last()
    rxyz = np.stack([rs["x"], rs["y"], rs["z"]], axis=1).astype(np.float64)
    aerial_b = xyz[label == BUILDING].astype(np.float64)
    cov0 = covered(samples, aerial_b).mean() if len(samples) else 0.0
    cov1 = covered(samples, np.concatenate([aerial_b, rxyz])).mean() if len(samples) else 0.0
    print(f"region {region} of round {rnd} (building {handed[0].ns}, {len(samples)} wall samples): "
          f"explorer coverage {before:.3f} -> {after:.3f}; within {TAU} m of a point: {cov0:.3f} -> {cov1:.3f}; "
          f"/resampled_cloud {len(rxyz)} points; {time.time() - t_start:.0f} s")
    assert after > before, (before, after)
    assert len(rxyz) > 1000
    assert "label" not in rs or (rs["label"] == BUILDING).all()
    assert len(samples) > 0 and cov1 > cov0, (cov0, cov1)
    for p in procs:
        assert p.p.poll() is None, f"{p.args[0]} exited {p.p.returncode}\n{logs()}"
