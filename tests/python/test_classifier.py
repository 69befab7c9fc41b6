"""scene_classifier over DDS with rclpy: the reference scene's airborne prior
goes in without labels and comes back whole with a `label` field that agrees
with the simulation's ground truth; malformed clouds are rejected on /rosout
and the node goes on."""
import subprocess

import numpy as np
import pytest

from conftest import BIN, qos, real_file
from test_detector import Clouds, cloud_msg, logs_of

GROUND, VEGETATION, BUILDING = 2, 5, 6


@pytest.fixture(scope="module")
def prior(tmp_path_factory):
    """x, y, z (float32) and true labels of `skyground aerial --scene reference`."""
    import laspy

    out = tmp_path_factory.mktemp("aerial")
    p = subprocess.run([str(BIN / "skyground"), "aerial", "--scene", "reference", "--out", str(out)],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-3000:]
    las = laspy.read(str(out / "aerial.las"))
    xyz = np.stack([las.x, las.y, las.z], axis=1).astype(np.float32)
    return xyz, np.asarray(las.classification, dtype=np.uint8)


def f1(pred, truth, cls):
    tp = np.sum((pred == cls) & (truth == cls))
    fp = np.sum((pred == cls) & (truth != cls))
    fn = np.sum((pred != cls) & (truth == cls))
    return 2 * tp / max(1, 2 * tp + fp + fn)


def started(spawn, ros):
    """A scene_classifier node with /rosout, its output and its input wired
    up: (logs, output clouds, input publisher, node)."""
    from rcl_interfaces.msg import Log
    from sensor_msgs.msg import PointCloud2

    logs = []
    ros.node.create_subscription(Log, "/rosout", logs.append, qos("reliable", 1000))
    got = Clouds(ros, "/classified_cloud")
    pub = ros.node.create_publisher(PointCloud2, "/aerial_cloud", qos("latched", 10))
    node = spawn("scene_classifier")
    assert ros.spin_until(lambda: pub.get_subscription_count() > 0, 30), node.stderr()
    return logs, got, pub, node


def unlabelled(xyz, stamp_sec):
    return cloud_msg({"x": xyz[:, 0], "y": xyz[:, 1], "z": xyz[:, 2]}, stamp_sec)


def test_reference_prior_comes_back_whole_and_labelled_like_the_truth(spawn, ros, prior):
    from sensor_msgs.msg import PointCloud2

    xyz, truth = prior
    # Every 4th point: ~10 pts/m², inside the shipped model's 1–46 pts/m², and a faster test.
    xyz, truth = xyz[::4], truth[::4]
    got = Clouds(ros, "/classified_cloud")
    pub = ros.node.create_publisher(PointCloud2, "/aerial_cloud", qos("latched", 1))
    node = spawn("scene_classifier")
    assert ros.spin_until(lambda: pub.get_subscription_count() > 0, 30), node.stderr()
    pub.publish(unlabelled(xyz, 7))
    assert ros.spin_until(lambda: got.done, 120), f"no /classified_cloud: {node.stderr()[-3000:]}"
    header, cols = got.done[-1]
    assert header.stamp.sec == 7 and header.frame_id == "map"
    assert "label" in cols, list(cols)
    assert len(cols["x"]) == len(xyz)
    np.testing.assert_array_equal(np.stack([cols["x"], cols["y"], cols["z"]], axis=1), xyz)
    pred = cols["label"]
    assert set(np.unique(pred)) <= {1, GROUND, VEGETATION, BUILDING}, np.unique(pred)
    scores = {c: f1(pred, truth, c) for c in (GROUND, VEGETATION, BUILDING)}
    print(f"{len(xyz)} points; F1 ground {scores[GROUND]:.3f}, vegetation {scores[VEGETATION]:.3f}, "
          f"building {scores[BUILDING]:.3f}")
    assert scores[BUILDING] >= 0.9, scores
    assert scores[GROUND] >= 0.95, scores
    assert scores[VEGETATION] >= 0.7, scores
    assert node.p.poll() is None, node.stderr()


def test_malformed_clouds_are_rejected_and_the_node_goes_on(spawn, ros, prior):
    from rcl_interfaces.msg import Log

    xyz, truth = prior
    xyz, truth = xyz[::8], truth[::8]
    logs, got, pub, node = started(spawn, ros)

    no_z = unlabelled(xyz[:1000], 1)
    no_z.fields = no_z.fields[:2]
    short = unlabelled(xyz[:1000], 2)
    short.data = bytes(short.data)[:-5]
    for k, (bad, expect) in enumerate([(no_z, "z"), (short, "data")]):
        pub.publish(bad)
        errors = lambda: [e.msg for e in logs_of(logs, "scene_classifier", Log.ERROR) if "rejected" in e.msg]  # noqa: E731
        assert ros.spin_until(lambda: len(errors()) > k, 20), f"no ERROR on /rosout for case {k}: {node.stderr()}"
        assert expect in errors()[k].lower() and "/aerial_cloud" in errors()[k], errors()[k]
    assert not got.done, "a malformed cloud must not be classified"
    assert node.p.poll() is None, node.stderr()

    pub.publish(unlabelled(xyz, 3))
    assert ros.spin_until(lambda: got.done, 120), f"no /classified_cloud after the bad ones: {node.stderr()[-3000:]}"
    header, cols = got.done[-1]
    assert header.stamp.sec == 3 and len(cols["label"]) == len(xyz)
    assert f1(cols["label"], truth, BUILDING) >= 0.85
    assert node.p.poll() is None, node.stderr()


def test_a_roof_where_the_survey_ends_is_taken_out_of_the_ground_and_logged(spawn, ros):
    """sample_c.las's roof runs to its east edge, where the cloth rests on
    it: the node says on /rosout what it took out of the ground, and no
    roof point 20 m over the street comes back as ground. Sent without
    echoes, the cloud is read by the model's forest trained without them,
    and the node says so."""
    import laspy
    from rcl_interfaces.msg import Log

    las = laspy.read(str(real_file("sample_c.las")))
    xyz = np.stack([las.x - las.x.min(), las.y - las.y.min(), las.z - las.z.min()], axis=1).astype(np.float32)
    theirs = np.asarray(las.classification)
    logs, got, pub, node = started(spawn, ros)
    pub.publish(unlabelled(xyz, 5))
    assert ros.spin_until(lambda: got.done, 120), f"no /classified_cloud: {node.stderr()[-3000:]}"
    said = lambda: [e.msg for e in logs_of(logs, "scene_classifier", Log.INFO) if "where the survey ends" in e.msg]  # noqa: E731
    assert ros.spin_until(lambda: said(), 20), f"nothing said on /rosout: {node.stderr()[-3000:]}"
    assert "1 roof piece(s)" in said()[0], said()
    # The cloud was sent without echo fields: the node says which forest read it.
    bare = lambda: [e.msg for e in logs_of(logs, "scene_classifier", Log.INFO) if "two returns" in e.msg]  # noqa: E731
    assert ros.spin_until(lambda: bare(), 20), f"no word on echoes: {node.stderr()[-3000:]}"
    assert "forest trained without echoes" in bare()[0], bare()
    pred = got.done[-1][1]["label"]
    street = np.median(xyz[theirs == 2, 2])
    assert not ((theirs == BUILDING) & (pred == GROUND) & (xyz[:, 2] > street + 20)).any()
    assert node.p.poll() is None, node.stderr()
