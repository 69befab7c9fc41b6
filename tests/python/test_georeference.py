"""The CRS over DDS: PointCloud2 carries local metres only, so cloud_publisher
also sends the file's frame latched on /georeference (one DiagnosticStatus
named `georeference`). A plain rclpy subscriber takes the cloud back to the
survey's coordinates and unit with it — `source = (origin + local) /
to_metre` — and gets the CRS itself (WKT for pyproj, the LAS records byte for
byte)."""
import numpy as np

from conftest import qos, real_file
from test_cloud_interop import fields_of, receive_clouds


def receive_georeference(ros, timeout=30.0):
    from diagnostic_msgs.msg import DiagnosticArray

    got = []
    ros.node.create_subscription(DiagnosticArray, "/georeference", got.append, qos("latched", 1))
    assert ros.spin_until(lambda: got, timeout), "no /georeference"
    (status,) = got[0].status
    assert status.name == "georeference"
    return got[0], status.message, {kv.key: kv.value for kv in status.values}


def to_source(xyz, values):
    origin = np.array([float(values[f"origin_{a}"]) for a in "xyz"])
    to_metre = np.array([float(values.get("to_metre_xy", 1.0))] * 2 + [float(values.get("to_metre_z", 1.0))])
    return (origin + xyz.astype(np.float64)) / to_metre


class Sent:
    """A real file published by cloud_publisher, as an rclpy subscriber gets it."""

    def __init__(self, spawn, ros, name):
        import laspy

        path = real_file(name)
        self.las = laspy.read(str(path))
        self.want = np.stack([self.las.x, self.las.y, self.las.z], axis=1)
        spawn("cloud_publisher", "--ros-args", "-p", f"file:={path}")
        self.msg, self.state, self.values = receive_georeference(ros)
        (self.tiles,) = receive_clouds(ros, "/aerial_cloud", "latched", 1)
        self.xyz, _ = fields_of(self.tiles)


def test_a_survey_in_us_feet_comes_back_in_its_crs_and_feet(spawn, ros):
    import pyproj

    s = Sent(spawn, ros, "laspy_nebraska_ftus.las")
    las, values, xyz, want = s.las, s.values, s.xyz, s.want
    assert s.state == "georeferenced" and s.msg.header.frame_id == s.tiles[0].header.frame_id == "map"
    assert values["epsg"] == "6880" and values["horizontal_unit"] == "US survey foot", values
    # Local metres are not feet: the cloud as sent is 3.28 × smaller than the file.
    span = np.ptp(xyz[:, 0])
    assert abs(np.ptp(want[:, 0]) / span - 1 / 0.3048006096) < 1e-3, span
    # Every point back in the file's feet, to the file's 0.001 ft resolution.
    np.testing.assert_allclose(to_source(xyz, values), want, rtol=0, atol=1e-3)
    # The CRS: pyproj reads the WKT sent as the one laspy reads from the file,
    # and the LAS records come back byte for byte.
    assert pyproj.CRS.from_wkt(values["wkt"]) == las.header.parse_crs()
    records = {}
    for r in values["las_records"].split(";"):
        rid, desc, data = r.split(",")
        records[int(rid)] = (bytes.fromhex(desc).decode(), bytes.fromhex(data))
    for v in las.header.vlrs:
        if v.user_id == "LASF_Projection":
            assert records[v.record_id] == (v.description, v.record_data_bytes()), v.record_id


def test_a_survey_without_crs_says_so_and_keeps_its_coordinates(spawn, ros):
    s = Sent(spawn, ros, "sample_c.las")
    assert s.state == "local metres, no CRS" and "wkt" not in s.values, (s.state, s.values)
    np.testing.assert_allclose(to_source(s.xyz, s.values), s.want, rtol=0, atol=1e-3)


def test_no_georeference_when_its_topic_is_empty(spawn, ros):
    from diagnostic_msgs.msg import DiagnosticArray

    got = []
    ros.node.create_subscription(DiagnosticArray, "/georeference", got.append, qos("latched", 1))
    spawn("cloud_publisher", "--ros-args", "-p", "synthetic_points:=1000", "-p", "georeference_topic:=")
    receive_clouds(ros, "/aerial_cloud", "latched", 1)
    ros.spin_until(lambda: got, 3.0)
    assert not got, "a georeference was sent with its topic empty"
