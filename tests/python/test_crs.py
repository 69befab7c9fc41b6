"""CRS and units end to end on the real files in feet: `skyground classify`
and `skyground detect` write LAS whose CRS (laspy `parse_crs()`, pyproj)
equals the input's and whose coordinates are in the input's feet; the
GeoJSON outputs name the CRS and hold coordinates in feet too; `skyground
info` reports the unit. No DDS: these are offline commands."""
import json
import subprocess

import numpy as np
import pytest

from conftest import BIN, ROOT, real_file

FEET = ["laspy_nebraska_ftus.las", "autzen_trim.las"]
# The classes `skyground classify` writes: unclassified, ground, vegetation,
# building, and bridge deck where a surface it took for a roof continues the
# terrain over lower ground (Autzen's footbridge).
OURS = {1, 2, 5, 6, 17}


def run(*args, timeout=600):
    p = subprocess.run([str(BIN / "skyground"), *map(str, args)], capture_output=True, text=True,
                       timeout=timeout)
    assert p.returncode == 0, p.stderr[-3000:]
    return p


def assert_same_crs_and_feet(src, out):
    import laspy

    a, b = laspy.read(str(src)), laspy.read(str(out))
    crs_in, crs_out = a.header.parse_crs(), b.header.parse_crs()
    assert crs_in is not None
    assert crs_out == crs_in, f"{out}: {crs_out!r} != {crs_in!r}"
    # Same points in the same unit: the extents agree to the written resolution.
    for axis in "xyz":
        got, want = np.asarray(getattr(b, axis)), np.asarray(getattr(a, axis))
        assert abs(got.min() - want.min()) < 0.01 and abs(got.max() - want.max()) < 0.01, axis
    assert len(b.points) == len(a.points)
    np.testing.assert_allclose(np.asarray(b.x), np.asarray(a.x), atol=0.002)


@pytest.mark.parametrize("name", FEET)
def test_classify_output_keeps_crs_and_feet(tmp_path, name):
    src = real_file(name)
    out = tmp_path / "classified.las"
    run("classify", "--in", src, "--out", out, "--json")
    assert_same_crs_and_feet(src, out)


@pytest.mark.parametrize("name", FEET)
def test_classify_changes_the_classes_and_nothing_else(tmp_path, name):
    """As a PDAL or LAStools classifier does: the producer's GPS time,
    colour, flight line, scan angle, flags, version and point format stay."""
    import laspy

    src = real_file(name)
    out = tmp_path / "classified.las"
    r = json.loads(run("classify", "--in", src, "--out", out, "--json").stdout)
    assert r["fields_kept"] is True
    a, b = laspy.read(str(src)), laspy.read(str(out))
    assert (b.header.version, b.point_format.id) == (a.header.version, a.point_format.id)
    assert [v.record_id for v in b.header.vlrs] == [v.record_id for v in a.header.vlrs]
    for dim in a.point_format.dimension_names:
        if dim != "classification":
            np.testing.assert_array_equal(np.asarray(b[dim]), np.asarray(a[dim]), err_msg=dim)
    # Our classes where the producer said ground, vegetation, building or
    # nothing; its noise (the Nebraska file's 25 class-7 points) and other
    # specific classes stay as they were.
    ours, theirs = np.asarray(b.classification), np.asarray(a.classification)
    kept = ~np.isin(theirs, [0, 1, 2, 3, 4, 5, 6, 8, 12])
    np.testing.assert_array_equal(ours[kept], theirs[kept])
    assert set(np.unique(ours[~kept])) <= OURS
    want = {str(k): int(v) for k, v in zip(*np.unique(theirs[kept], return_counts=True))}
    assert r["producer_classes_kept"] == want
    assert (name != "laspy_nebraska_ftus.las") or want == {"7": 25}, want
    if name == "autzen_trim.las":
        # Ground and unclassified only: unclassified is not known to be off
        # the ground (much of Autzen's lies on it), so only its ground is judged.
        g = r["ground"]
        assert (g["scope"], g["points"], g["type_ii"], g["kappa"]) == ("producer ground only", 26_107, None, None), g
        assert g["total_error"] == g["type_i"] < 0.25, g
    counts = {int(k): v for k, v in zip(*np.unique(ours, return_counts=True))}
    assert counts.get(6, 0) == r["classes"].get("building", 0)
    assert counts.get(17, 0) == r["at_grade"]["to_bridge_deck"] == r["classes"].get("bridge deck", 0), r
    # Written over its own input, the file is replaced whole, not half-read.
    again = tmp_path / "again.las"
    again.write_bytes(out.read_bytes())
    run("classify", "--in", again, "--out", again)
    np.testing.assert_array_equal(np.asarray(laspy.read(str(again)).gps_time), np.asarray(a.gps_time))


@pytest.mark.parametrize("name", FEET)
def test_detect_outputs_keep_crs_and_feet(tmp_path, name):
    import laspy

    src = real_file(name)
    out = tmp_path / "detect"
    summary = json.loads(run("detect", "--in", src, "--out", out, "--classify", "--json").stdout)
    assert summary["crs"]["unit"] in ("foot", "US survey foot"), summary["crs"]
    assert_same_crs_and_feet(src, out / "classified.las")
    crs_in = laspy.read(str(src)).header.parse_crs()
    missing = laspy.read(str(out / "missing.las"))
    assert missing.header.parse_crs() == crs_in
    hdr = laspy.read(str(src)).header
    lo, hi = hdr.mins - 100, hdr.maxs + 100
    for f in ["targets.geojson", "completeness.geojson"]:
        doc = json.loads((out / f).read_text())
        assert doc["units"]["horizontal"] == summary["crs"]["unit"]
        assert "crs" in doc, f
        for feat in doc["features"]:
            g = feat["geometry"]
            pts = {"Point": lambda c: [c], "Polygon": lambda c: c[0],
                   "MultiPolygon": lambda c: [p for poly in c for p in poly[0]]}[g["type"]](g["coordinates"])
            for p in pts:
                assert lo[0] <= p[0] <= hi[0] and lo[1] <= p[1] <= hi[1], (f, p)
    csv = (out / "completeness.csv").read_text().splitlines()
    assert csv[0].startswith("building,footprint_id,centroid_x_ft"), csv[0]


@pytest.mark.parametrize("name,unit", [("laspy_nebraska_ftus.las", "US survey foot"), ("autzen_trim.las", "foot"),
                                       ("sample_c.las", "metre")])
def test_info_reports_unit_and_extent_in_both(name, unit):
    import laspy

    src = real_file(name)
    info = json.loads(run("info", src, "--json").stdout)
    assert info["crs"]["unit"] == unit
    hdr = laspy.read(str(src)).header
    size = hdr.maxs - hdr.mins
    np.testing.assert_allclose(info["extent"]["size"], size, atol=0.01)
    np.testing.assert_allclose(info["extent"]["size_m"], size * info["crs"]["to_metre"], atol=0.01)
    assert info["points"] == hdr.point_count
    assert sum(info["classes"].values()) == hdr.point_count
    assert sum(info["returns"].values()) == hdr.point_count
    # Echoes count for the classifier only when some pulse gave two returns
    # (the Nebraska snippet: every point 1 of 1).
    las = laspy.read(str(src))
    assert info["echoes_usable"] == bool((np.asarray(las.number_of_returns) > 1).any())
    assert info["echoes_usable"] == (name != "laspy_nebraska_ftus.las")


def test_footprints_and_plan_in_feet(tmp_path):
    """Footprints drawn in the survey's feet (here: detect's own outlines,
    written in feet) load onto the same buildings; `plan` starts on the
    largest piece of ground and writes its route in feet."""
    src = real_file("autzen_trim.las")
    first = json.loads(run("detect", "--in", src, "--out", tmp_path / "a", "--json").stdout)
    given = json.loads(run("detect", "--in", src, "--out", tmp_path / "b", "--json",
                           "--footprints", tmp_path / "a" / "completeness.geojson").stdout)
    assert given["footprints"] == "given"
    assert given["footprints_used"] == first["footprints_used"] > 0
    # The outlines split the same points off (metres would miss them by 3.3×).
    inside = [sum(b["points"] for b in d["per_building"]) for d in (first, given)]
    assert inside[0] > 0 and abs(inside[1] - inside[0]) <= 0.05 * inside[0], inside
    plan = json.loads(run("plan", "--in", tmp_path / "a", "--json").stdout)
    assert plan["nodes"] > 1000 and plan["reachable_node_share"] > 0.5, plan["graph"]
    assert plan["reachable_points"] + plan["reachable_regions"] > 0, plan
    route = json.loads((tmp_path / "a" / "route.geojson").read_text())
    assert route["units"]["horizontal"] == "foot"
    hdr = __import__("laspy").read(str(src)).header
    lines = [f for f in route["features"] if f["geometry"]["type"] == "LineString"]
    assert lines, "no route line"
    inside = lambda x, y: hdr.mins[0] - 1 <= x <= hdr.maxs[0] + 1 and hdr.mins[1] - 1 <= y <= hdr.maxs[1] + 1
    for x, y, *_ in lines[0]["geometry"]["coordinates"]:
        assert inside(x, y), (x, y)
    # One route per set-down; each set-down after the first is a Point in
    # feet where the team puts the robot down, and reaches targets.
    assert [f["properties"]["set_down"] for f in lines] == list(range(1, len(plan["set_downs"]) + 1))
    puts = [f for f in route["features"] if f["properties"]["kind"] == "set_down"]
    assert len(puts) == len(plan["set_downs"]) - 1
    for f in puts:
        assert inside(*f["geometry"]["coordinates"][:2]), f
        assert f["properties"]["stops"] > 0 and "set the robot down here" in f["properties"]["why"]
    assert sum(s["stops"] for s in plan["set_downs"]) == plan["stops"]
    # The plan's picture: a PNG as wide as the survey is long (2,400 px on
    # its longer side, autzen_trim is 1,178 × 563 ft), with the legend in a
    # band above the map and the scale bar in one below it (under 300 px).
    png = (tmp_path / "a" / "plan.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
    assert width == 2400 and 1000 < height < 1600, (width, height)


def test_classify_a_file_whose_producer_names_no_ground(tmp_path):
    """Labels but no class 2–6 (water and unclassified only): classified,
    the water kept, no accuracy or ground figures claimed."""
    import laspy

    las = laspy.read(str(real_file("sample_c.las")))
    codes = np.ones(len(las.points), dtype=np.uint8)
    codes[:100] = 9
    las.classification = codes
    src, out = tmp_path / "water.las", tmp_path / "out.las"
    las.write(str(src))
    r = json.loads(run("classify", "--in", src, "--out", out, "--json").stdout)
    assert r["ground"] is None and r["report"]["points"] == 0, (r["ground"], r["report"]["points"])
    assert r["producer_classes_kept"] == {"9": 100}
    got = np.asarray(laspy.read(str(out)).classification)
    assert (got[:100] == 9).all() and set(np.unique(got[100:])) <= OURS


def test_classify_takes_a_roof_where_the_survey_ends_out_of_the_ground(tmp_path):
    """sample_c.las's roof runs to the file's east edge, and the cloth rested
    on it there: `classify` reports the piece it took out, and in the file
    it writes no producer-building point stands as ground 20 m over the
    street. A cut of the file without that edge reports nothing taken."""
    import laspy

    src, out = real_file("sample_c.las"), tmp_path / "out.las"
    r = json.loads(run("classify", "--in", src, "--out", out, "--json").stdout)
    assert r["raised_ground"]["pieces"] == 1 and 500 <= r["raised_ground"]["points"] <= 600, r["raised_ground"]
    assert r["ground"]["total_error"] < 0.01, r["ground"]
    a, b = laspy.read(str(src)), laspy.read(str(out))
    theirs, ours, z = np.asarray(a.classification), np.asarray(b.classification), np.asarray(a.z)
    street = np.median(z[theirs == 2])
    assert not ((theirs == 6) & (ours == 2) & (z > street + 20)).any()
    # Without the roof's east edge: nothing to take out.
    x = np.asarray(a.x)
    keep = x < x.min() + 40
    cut = tmp_path / "west.las"
    w = laspy.LasData(a.header)
    w.points = a.points[keep]
    w.write(str(cut))
    r = json.loads(run("classify", "--in", cut, "--out", tmp_path / "w.las", "--json").stdout)
    assert r["raised_ground"] == {"pieces": 0, "points": 0}, r["raised_ground"]


def test_detect_classifies_with_the_model_it_is_given(tmp_path):
    """`detect --classify --model M` classifies with M (here the shipped
    model's file: the same classes as without it); a model that cannot be
    read is a clear error, and --model without --classify is refused."""
    import laspy

    src = real_file("sample_c.las")
    model = ROOT / "config" / "classifier_model.json.gz"
    a = json.loads(run("detect", "--in", src, "--out", tmp_path / "a", "--classify", "--json").stdout)
    b = json.loads(run("detect", "--in", src, "--out", tmp_path / "b", "--classify", "--model", model,
                       "--json").stdout)
    ca, cb = (laspy.read(str(tmp_path / d / "classified.las")).classification for d in "ab")
    assert np.array_equal(np.asarray(ca), np.asarray(cb))
    assert a["producer_check"] == b["producer_check"]
    bad = tmp_path / "not_a_model.json"
    bad.write_text("{}")
    p = subprocess.run([str(BIN / "skyground"), "detect", "--in", str(src), "--out", str(tmp_path / "c"),
                        "--classify", "--model", str(bad)], capture_output=True, text=True, timeout=600)
    assert p.returncode != 0 and "classifier model" in p.stderr and "not_a_model.json" in p.stderr, p.stderr
    p = subprocess.run([str(BIN / "skyground"), "detect", "--in", str(src), "--out", str(tmp_path / "d"),
                        "--model", str(model)], capture_output=True, text=True, timeout=600)
    assert p.returncode != 0 and "--classify" in p.stderr, p.stderr


def test_detect_says_what_it_found(tmp_path):
    """Without --json, `detect` tells a user on stderr what it found and
    where it wrote it (the same counts as the JSON), and keeps stdout empty."""
    src = real_file("laspy_nebraska_ftus.las")
    s = json.loads(run("detect", "--in", src, "--out", tmp_path / "a", "--json").stdout)
    p = run("detect", "--in", src, "--out", tmp_path / "b")
    assert p.stdout == ""
    line = p.stderr.splitlines()[0]
    assert line.startswith(
        f"{s['buildings']} buildings ({s['analysed']} analysed), {s['missing_points']} missing points"
    ), line
    assert f"{s['target_points']} target points and {s['target_regions']} regions" in line, line
    assert str(tmp_path / "b") in line and "targets.geojson" in line, line
    assert "against the producer's classes" in p.stderr, p.stderr


def test_detect_and_plan_a_tile_without_buildings(tmp_path):
    """A survey tile with no building (a park, a field) is an answer, not an
    error: `detect` writes every output with 0 buildings and 0 targets (its
    picture spans the tile), `plan` plans nothing and `reconstruct` models
    nothing. Before, `detect` stopped with "nothing to draw" after writing
    half its outputs."""
    import laspy

    full = laspy.read(str(real_file("sample_c.las")))
    ground = laspy.LasData(full.header)
    ground.points = full.points[np.asarray(full.classification) == 2]
    src = tmp_path / "ground_only.las"
    ground.write(str(src))
    out = tmp_path / "detect"
    s = json.loads(run("detect", "--in", src, "--out", out, "--json").stdout)
    assert (s["buildings"], s["target_points"], s["target_regions"]) == (0, 0, 0), s
    for f in ["detection.png", "detection.json", "targets.json", "missing.las", "completeness.csv"]:
        assert (out / f).exists(), f
    assert json.loads((out / "targets.geojson").read_text())["features"] == []
    assert laspy.read(str(out / "classified.las")).header.parse_crs() == full.header.parse_crs()
    png = (out / "detection.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    w, h = int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
    span = ground.header.maxs - ground.header.mins
    assert abs(w / h - span[0] / span[1]) < 0.35 * span[0] / span[1], (w, h, span)
    p = json.loads(run("plan", "--in", out, "--json").stdout)
    assert (p["target_points"], p["target_regions"], p["stops"]) == (0, 0, 0), p
    assert p["nodes"] > 0, "the ground graph is built all the same"
    # No buildings, no models: an empty, valid CityJSON (before: "classify it first").
    r = json.loads(run("reconstruct", "--in", out / "classified.las", "--out", tmp_path / "m", "--json").stdout)
    assert r["models"] == 0 and r["per_model"] == [], r
    doc = json.loads((tmp_path / "m" / "models.city.json").read_text())
    assert doc["CityObjects"] == {} and doc["vertices"] == [], doc


def test_reconstruct_writes_models_in_the_clouds_feet_and_crs(tmp_path):
    """LoD2 models of a cloud in US survey feet: models.city.json names the
    file's CRS (metadata.referenceSystem) and holds its vertices in feet, as
    do the OBJ and reconstruct.json's bases; cjval finds the file valid.
    Before, the models came out in metres with no CRS."""
    import os

    import laspy

    src = real_file("laspy_nebraska_ftus.las")
    classified = tmp_path / "classified.las"
    run("classify", "--in", src, "--out", classified)
    out = tmp_path / "models"
    r = json.loads(run("reconstruct", "--in", classified, "--out", out, "--json").stdout)
    epsg = laspy.read(str(src)).header.parse_crs().to_epsg()
    assert (r["crs"]["epsg"], r["crs"]["unit"]) == (epsg, "US survey foot"), r["crs"]
    assert r["models"] >= 1, r
    hdr = laspy.read(str(src)).header
    lo, hi = hdr.mins - 5, hdr.maxs + 5
    doc = json.loads((out / "models.city.json").read_text())
    assert doc["metadata"]["referenceSystem"] == f"https://www.opengis.net/def/crs/EPSG/0/{epsg}"
    t = doc["transform"]
    xyz = np.asarray(doc["vertices"], dtype=float) * t["scale"] + t["translate"]
    assert (xyz >= lo).all() and (xyz <= hi).all(), (xyz.min(axis=0), xyz.max(axis=0), lo, hi)
    obj = np.asarray([line.split()[1:] for line in (out / "models.obj").read_text().splitlines()
                      if line.startswith("v ")], dtype=float)
    assert (obj >= lo).all() and (obj <= hi).all(), (obj.min(axis=0), obj.max(axis=0))
    for m in r["per_model"]:
        assert lo[2] <= m["base"] <= hi[2], m["base"]
    cjval = os.environ.get("SKYGROUND_CJVAL")
    if cjval:
        p = subprocess.run([cjval, "-s", str(out / "models.city.json")], capture_output=True, text=True,
                           timeout=120)
        text = p.stdout + p.stderr
        assert "File is valid" in text and "File is invalid" not in text, text


def test_aerial_survey_of_a_city_model_keeps_its_crs(tmp_path):
    """The simulated survey of a CityJSON model in EPSG:7415 is written in
    that CRS (laspy/pyproj read it back) at the model's coordinates, as the
    mission's aerial.las and resampled.las are. Before, it named no CRS."""
    import laspy

    model = real_file("3dbag_2buildings.city.json")
    doc = json.loads(model.read_text())
    t = doc["transform"]
    v = np.asarray(doc["vertices"], dtype=float) * t["scale"] + t["translate"]
    run("aerial", "--scene", model, "--out", tmp_path / "a")
    las = laspy.read(str(tmp_path / "a" / "aerial.las"))
    assert las.header.parse_crs().to_epsg() == 7415, las.header.parse_crs()
    # The survey reaches past the buildings (ground around them), not elsewhere.
    for k, axis in enumerate("xy"):
        c = np.asarray(getattr(las, axis))
        assert v[:, k].min() - 100 < c.min() <= v[:, k].min(), axis
        assert v[:, k].max() <= c.max() < v[:, k].max() + 100, axis


def in_us_feet(model, out, epsg=2263):
    """`model` with its coordinates in US survey feet, naming a CRS in them
    (the same buildings: only the unit and the CRS label change)."""
    doc = json.loads(model.read_text())
    ft = 1200 / 3937
    t = doc["transform"]
    t["scale"] = [s / ft for s in t["scale"]]
    t["translate"] = [v / ft for v in t["translate"]]
    doc["metadata"]["referenceSystem"] = f"https://www.opengis.net/def/crs/EPSG/0/{epsg}"
    for o in [doc["metadata"], *doc["CityObjects"].values()]:
        if "geographicalExtent" in o:
            o["geographicalExtent"] = [e / ft for e in o["geographicalExtent"]]
    out.write_text(json.dumps(doc))
    return out, ft


def test_a_city_model_in_feet_is_simulated_in_metres_and_written_in_feet(tmp_path):
    """A CityJSON model in US survey feet (as New York's is, EPSG:2263): the
    buildings are read in metres (not 3.28 times their size), the simulated
    survey is written in the model's feet and CRS, and `eval` measures it
    against the model as it measures the same survey in metres. Before, the
    scene was read as metres and aerial.las named no CRS."""
    import laspy

    model = real_file("3dbag_2buildings.city.json")
    feet, ft = in_us_feet(model, tmp_path / "feet.city.json")
    run("aerial", "--scene", model, "--out", tmp_path / "m")
    run("aerial", "--scene", feet, "--out", tmp_path / "f")
    m = laspy.read(str(tmp_path / "m" / "aerial.las"))
    f = laspy.read(str(tmp_path / "f" / "aerial.las"))
    assert f.header.parse_crs().to_epsg() == 2263, f.header.parse_crs()
    assert abs(len(f.points) - len(m.points)) <= 0.005 * len(m.points), (len(f.points), len(m.points))
    # The same survey, in feet: extents agree within 5 cm once scaled back.
    fm = [np.asarray(getattr(f, a)) * ft for a in "xyz"]
    mm = [np.asarray(getattr(m, a)) for a in "xyz"]
    for k, axis in enumerate("xyz"):
        assert abs(fm[k].min() - mm[k].min()) < 0.05, axis
        assert abs(fm[k].max() - mm[k].max()) < 0.05, axis
    cov = {}
    for name, scene, d in [("m", model, "m"), ("f", feet, "f")]:
        las = tmp_path / d / "aerial.las"
        e = json.loads(run("eval", "--aerial", las, "--resampled", las, "--scene", scene, "--json").stdout)
        cov[name] = e["coverage_before"]
    assert cov["m"] > 0.9 and abs(cov["f"] - cov["m"]) < 0.002, cov
    # `info` tells the model's extent in its own unit: feet, the same metres.
    im, jf = (json.loads(run("info", s, "--json").stdout)["extent"] for s in (model, feet))
    for k in range(3):
        assert abs(jf["size_m"][k] - im["size_m"][k]) < 0.01, (jf, im)
        assert abs(jf["min"][k] * ft - im["min"][k]) < 0.01, (jf, im)
        assert abs(jf["size"][k] * ft - im["size"][k]) < 0.01, (jf, im)


def test_a_mission_on_a_city_model_in_feet_is_written_in_feet(tmp_path, env):
    """The demo's closed loop over the same model in feet: it finishes and
    gains as over the model in metres, and what it writes for the field
    (merged cloud, driven route, per-building completeness, LoD2 models) is
    in the model's feet and names EPSG:2263."""
    import laspy

    model = real_file("3dbag_2buildings.city.json")
    feet, ft = in_us_feet(model, tmp_path / "feet.city.json")
    doc = json.loads(model.read_text())
    t = doc["transform"]
    v = (np.asarray(doc["vertices"], dtype=float) * t["scale"] + t["translate"]) / ft
    lo, hi = v.min(axis=0), v.max(axis=0)
    out = tmp_path / "out"
    p = subprocess.run([str(BIN / "skyground"), "demo", "--scene", str(feet), "--out", str(out),
                        "--timeout", "300"], capture_output=True, text=True, timeout=600, env=env)
    assert p.returncode == 0, p.stderr[-4000:]
    report = json.loads((out / "report.json").read_text())
    assert report["finished"] is True
    assert report["coverage_after"] > report["coverage_before"] + 0.02, report["coverage_after"]
    # Around the two buildings (the survey reaches 100 m past them), in feet.
    near = lambda x, y: lo[0] - 400 < x < hi[0] + 400 and lo[1] - 400 < y < hi[1] + 400
    las = laspy.read(str(out / "resampled.laz"))
    assert las.header.parse_crs().to_epsg() == 2263
    assert near(las.header.mins[0], las.header.mins[1]) and near(las.header.maxs[0], las.header.maxs[1])
    route = json.loads((out / "route.geojson").read_text())
    assert route["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::2263"
    driven = route["features"][0]
    assert abs(driven["properties"]["length"] * ft - report["path_length_m"]) < 0.05
    assert all(near(x, y) for x, y, *_ in driven["geometry"]["coordinates"])
    fp = json.loads((out / "completeness.geojson").read_text())
    assert fp["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::2263"
    ring = np.asarray(fp["features"][0]["geometry"]["coordinates"][0][0])
    assert (ring.min(axis=0) > lo[:2] - 3).all() and (ring.max(axis=0) < hi[:2] + 3).all(), ring
    m = json.loads((out / "models_after.city.json").read_text())
    assert m["metadata"]["referenceSystem"].endswith("/EPSG/0/2263")
    e = m["metadata"]["geographicalExtent"]
    assert near(e[0], e[1]) and near(e[3], e[4]), e


def test_a_crs_the_file_does_not_state(tmp_path):
    """AHN3 tiles come without CRS records; `--crs EPSG:28992` gives every
    output the CRS (LAS 1.2 copy: GeoTIFF keys; LAS 1.4: WKT; GeoJSON: its
    URN), as laspy/pyproj read them; a file that states another CRS is
    refused with nothing written, and a name that is no EPSG code too."""
    import laspy
    import pyproj

    src = real_file("ahn3_delft_2.laz")
    assert laspy.read(str(src)).header.parse_crs() is None
    out = tmp_path / "d"
    s = json.loads(run("detect", "--in", src, "--out", out, "--crs", "EPSG:28992", "--json").stdout)
    assert s["crs"]["epsg"] == 28992, s["crs"]
    rd = pyproj.CRS.from_epsg(28992)
    copy = laspy.read(str(out / "classified.laz"))
    assert copy.header.version == laspy.read(str(src)).header.version
    assert copy.header.parse_crs() == rd
    missing = laspy.read(str(out / "missing.las")).header.parse_crs()
    # RD New itself, not a bound CRS around it (the registry's datum shift is left out).
    assert missing == rd and missing.to_epsg() == 28992, missing.to_wkt()
    for f in ["targets.geojson", "completeness.geojson"]:
        doc = json.loads((out / f).read_text())
        assert doc["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::28992", f
    info = run("info", src, "--crs", "28992").stdout
    assert "EPSG:28992" in info and "from epsg" in info, info
    # Stated again where the file states its own: the same is accepted, another refused.
    feet = real_file("autzen_trim.las")
    run("info", feet, "--crs", "EPSG:2994")
    for args in (["--crs", "EPSG:28992"], ["--crs", "RD New"]):
        p = subprocess.run([str(BIN / "skyground"), "detect", "--in", str(feet if args[1] != "RD New" else src),
                            "--out", str(tmp_path / "x"), *args], capture_output=True, text=True, timeout=600)
        assert p.returncode != 0, p.stderr
        assert not (tmp_path / "x" / "targets.geojson").exists()
        assert ("does not reproject" in p.stderr) if args[1] != "RD New" else ("names no EPSG code" in p.stderr), p.stderr


def test_crs_records_nobody_can_read(tmp_path):
    """A file whose CRS records are malformed (a GeoKeyDirectory shorter
    than its key count; a LAS 1.4 extended WKT record of 600 kB of nested
    brackets, which overflowed the parser's stack and aborted the process)
    is refused with the fault and the way round it named; with `--crs` its
    points are read all the same, and the output carries the stated CRS in
    place of the records nobody can read."""
    import struct

    import laspy
    import pyproj
    from laspy.vlrs.vlrlist import VLRList

    src = laspy.read(str(real_file("sample_c.las")))
    assert src.header.parse_crs() is None
    keys = tmp_path / "keys.las"
    # Version 1.1.0, 4 keys declared, one given.
    directory = struct.pack("<8H", 1, 1, 0, 4, 1024, 0, 1, 1)
    src.header.vlrs.append(laspy.VLR(user_id="LASF_Projection", record_id=34735,
                                     description="GeoKeyDirectoryTag", record_data=directory))
    src.write(str(keys))

    deep = tmp_path / "deep.las"
    d = laspy.convert(laspy.read(str(real_file("sample_c.las"))), point_format_id=6, file_version="1.4")
    d.header.evlrs = VLRList()
    nested = b"A[" * 200_000 + b"]" * 200_000 + b"\0"
    d.header.evlrs.append(laspy.VLR(user_id="LASF_Projection", record_id=2112, description="OGC WKT",
                                    record_data=nested))
    d.write(str(deep))

    lambert = pyproj.CRS.from_epsg(2154)
    for f, fault in [(keys, "declares 4 keys"), (deep, "nested at most 64 deep")]:
        p = subprocess.run([str(BIN / "skyground"), "info", str(f)], capture_output=True, text=True, timeout=600)
        assert p.returncode == 1, (p.returncode, p.stderr)
        assert fault in p.stderr and "--crs EPSG:N" in p.stderr, p.stderr
        out = tmp_path / f"{f.stem}_classified.las"
        r = run("classify", "--in", f, "--out", out, "--crs", "EPSG:2154", "--json")
        assert fault in r.stderr and "taken in EPSG:2154" in r.stderr, r.stderr
        back = laspy.read(str(out))
        assert back.header.parse_crs() == lambert
        assert len(back.points) == len(src.points)
        assert json.loads(r.stdout)["report"]["per_class"], "the producer's classes are scored"
        projection = [v.record_id for v in [*back.header.vlrs, *(back.header.evlrs or [])]
                      if v.user_id == "LASF_Projection"]
        assert projection.count(34735) == 1 if f == keys else projection == [2112], projection
        assert not any(len(v.record_data) > 10_000 for v in back.header.evlrs or [])


def test_classify_says_the_roof_check_it_applied(tmp_path):
    """The roof check's cell and link follow the point spacing below
    4 pts/m², its growing angle below about 8, and they are the model's
    above: `classify --json` says which."""
    import laspy

    src = real_file("ahn3_delft_2.laz")
    full = json.loads(run("classify", "--in", src, "--json").stdout)
    assert (full["roof_check"]["cell_m"], full["roof_check"]["link_m"]) == (0.5, 1.0), full["roof_check"]
    las = laspy.read(str(src))
    pulse = np.cumsum(np.asarray(las.return_number) <= 1) - 1
    sparse = laspy.LasData(las.header)
    sparse.points = las.points[pulse % 5 == 0]
    thin = tmp_path / "sparse.las"
    sparse.write(str(thin))
    r = json.loads(run("classify", "--in", thin, "--json").stdout)
    s = r["density"]["spacing_m"]
    assert r["density"]["points_per_m2"] < 4 and s > 0.5, r["density"]
    assert r["roof_check"]["cell_m"] == pytest.approx(s) and r["roof_check"]["link_m"] == pytest.approx(2 * s)
    # The growing angle widens by the spacing over the voxel, and the
    # roofs' multiple-return share is bounded; the full file keeps both.
    voxel = r["roof_check"]["voxel_m"]
    assert r["roof_check"]["grow_angle_deg"] == pytest.approx(min(40.0, 12.0 * s / voxel), rel=1e-4)
    assert r["roof_check"]["max_multiple_share"] == pytest.approx(0.3)
    assert (full["roof_check"]["grow_angle_deg"], full["roof_check"]["max_multiple_share"]) == (12.0, 1.0)
    building = next(c for c in r["report"]["per_class"] if c["class"] == 6)
    assert building["f1"] >= 0.8, building
