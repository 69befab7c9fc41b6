"""Tiles of one survey as one cloud: `skyground classify` and `skyground
detect` take several files, as producers deliver a survey (tiles side by
side in one CRS). A building the seam cuts is found once, whole, the ground
graph runs across the seam, and tiles in different CRSs are refused with
both names. The two AHN3 Delft tiles meet at x = 85,000 m. No DDS."""
import json
import subprocess

import pytest

from conftest import BIN, real_file
from test_crs import run


def detect(tmp_path, name, *files):
    out = tmp_path / name
    summary = json.loads(run("detect", "--in", *files, "--out", out, "--json").stdout)
    plan = json.loads(run("plan", "--in", out, "--json").stdout)
    return summary, plan


def plan_with_closed_crowns(tmp_path, out):
    """`skyground plan` on `out` with vegetation blocking its whole column."""
    params = tmp_path / "column.yaml"
    params.write_text("global_planner:\n  ros__parameters:\n    graph:\n      canopy_is_obstacle: true\n")
    p = subprocess.run([str(BIN / "skyground"), "plan", "--in", out, "--params-file", params, "--json"],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    return p


def test_adjacent_tiles_are_one_survey(tmp_path):
    import laspy

    d1, d2 = real_file("ahn3_delft_1.laz"), real_file("ahn3_delft_2.laz")
    alone = [detect(tmp_path, f.stem, f) for f in (d1, d2)]
    both, plan = detect(tmp_path, "both", d1, d2)
    assert both["inputs"] == [str(d1), str(d2)]
    assert both["points"] == sum(s["points"] for s, _ in alone)
    # Buildings across the seam are counted once, not once per tile.
    counts = [s["buildings"] for s, _ in alone]
    assert max(counts) < both["buildings"] < sum(counts), (counts, both["buildings"])
    # Joined at the seam, the start's piece of ground is larger than either tile's.
    nodes = [p["graph"]["nodes"] for _, p in alone]
    assert plan["graph"]["nodes"] > max(nodes) * 1.5, (nodes, plan["graph"]["nodes"])
    # The targets still stand beside the producer's buildings.
    check = both["producer_check"]
    assert check["targets"] > 0 and check["targets_beyond_reach"] == 0, check
    assert check["missing_on_outline_share"] >= 0.95, check
    # At their density (about 10 pts/m²) outlines are drawn in 0.5 m cells,
    # so the outline reach is the half metre.
    assert check["outline_reach_m"] == 0.5, check
    assert check["missing_within_half_metre"] == check["missing_on_outline"], check
    # LAZ tiles in, LAZ out.
    classified = tmp_path / "both" / "classified.laz"
    assert both["outputs"]["classified"] == str(classified)
    las = laspy.read(str(classified))
    assert len(las.points) == both["points"]
    assert las.x.min() < 85000.0 - 100 and las.x.max() > 85000.0 + 50


def test_tiles_classified_together_and_scored(tmp_path):
    import laspy

    d1, d2 = real_file("ahn3_delft_1.laz"), real_file("ahn3_delft_2.laz")
    out = tmp_path / "both.las"
    r = json.loads(run("classify", "--in", d1, d2, "--out", out, "--json").stdout)
    assert r["inputs"] == [str(d1), str(d2)] and not r["trained_on_this_file"]
    las = laspy.read(str(out))
    assert len(las.points) == r["points"] == 640_510 + 208_432
    building = next(c for c in r["report"]["per_class"] if c["class"] == 6)
    # The shipped model on each tile alone: 0.952 and 0.973 (docs/classification.md).
    assert building["f1"] >= 0.93, building
    assert r["ground"]["total_error"] <= 0.05, r["ground"]
    # The producer's own labels against their neighbours' majority, on an
    # even sample: AHN3's building class agrees with itself.
    coherence = {c["k"]: c for c in r["label_coherence"]}
    assert set(coherence) == {4, 16}
    assert 100_000 < coherence[4]["sampled"] <= 200_000, coherence[4]["sampled"]
    itself = next(c for c in coherence[16]["report"]["per_class"] if c["class"] == 6)
    assert itself["f1"] >= 0.98 and itself["f1"] > building["f1"], itself
    # What the points look like: AHN3 names no vegetation, so two pairings;
    # the building points we call vegetation are scattered and split the
    # pulse more often than those we agree on (0.38 / 0.48 against 0.63 /
    # 0.15 on Delft 1 alone).
    shapes = {(p["producer"], p["ours"]): p for p in r["shapes_by_pairing"]}
    assert set(shapes) == {(6, 6), (6, 5)}, shapes.keys()
    agreed, missed = shapes[(6, 6)], shapes[(6, 5)]
    assert agreed["points"] + missed["points"] <= r["points"]
    assert 1000 < missed["sampled"] <= 5000 and missed["sampled"] <= missed["points"]
    assert missed["planarity_median"] < agreed["planarity_median"] - 0.15, shapes
    assert missed["multiple_returns_share"] > agreed["multiple_returns_share"] + 0.15, shapes


@pytest.mark.parametrize("cmd", ["classify", "detect"])
def test_tiles_in_different_crs_are_refused(tmp_path, cmd):
    d2, autzen = real_file("ahn3_delft_2.laz"), real_file("autzen_trim.las")
    p = subprocess.run([str(BIN / "skyground"), cmd, "--in", d2, autzen, "--out", tmp_path / "x"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode != 0
    assert "different horizontal CRSs" in p.stderr and "EPSG:2994" in p.stderr, p.stderr
    assert d2.name in p.stderr and autzen.name in p.stderr, p.stderr
    assert not (tmp_path / "x").exists() or not any((tmp_path / "x").iterdir())


def test_tile_by_tile_with_a_buffer(tmp_path):
    """`--out-dir`: each tile is classified with its neighbour's points within
    the buffer and written alone, under its own name, with its own points."""
    d1, d2 = real_file("ahn3_delft_1.laz"), real_file("ahn3_delft_2.laz")
    out = tmp_path / "classified"
    r = json.loads(run("classify", "--in", d1, d2, "--out-dir", out, "--buffer", "30", "--json").stdout)
    assert r["buffer_m"] == 30 and len(r["tiles"]) == 2
    # The 0.952 and 0.973 of each tile alone (docs/classification.md); the buffer gives the
    # narrow Delft 2 its neighbour's ground across the seam.
    for t, src, floor in zip(r["tiles"], (d1, d2), (0.93, 0.96)):
        assert t["output"] == str(out / src.name), t["output"]
        assert 50_000 < t["buffer_points"] < t["points"], t["buffer_points"]
        building = next(c for c in t["report"]["per_class"] if c["class"] == 6)
        assert building["f1"] >= floor, (src.name, building)
        assert t["ground"]["total_error"] <= 0.05, t["ground"]
        # Profiled on the tile's own points, not its neighbour's.
        agreed = next(p for p in t["shapes_by_pairing"] if (p["producer"], p["ours"]) == (6, 6))
        assert agreed["points"] == round(building["support"] * building["recall"]), (agreed, building)
    # Each output (LAZ, as its input) is its own tile's points: none of the
    # neighbour's come along.
    for src in (d1, d2):
        got, want = (json.loads(run("info", f, "--json").stdout) for f in (out / src.name, src))
        assert got["points"] == want["points"]
        assert got["extent"]["min"] == pytest.approx(want["extent"]["min"], abs=0.01)
        assert got["extent"]["max"] == pytest.approx(want["extent"]["max"], abs=0.01)
        # Ours, and AHN3's water (9) and civil structures (26) as they were.
        kept = {c: n for c, n in want["classes"].items() if c in ("9", "26")}
        assert kept and set(got["classes"]) <= {"1", "2", "5", "6"} | set(kept), got["classes"]
        assert all(got["classes"][c] == n for c, n in kept.items()), (got["classes"], kept)


def test_an_out_dir_holding_an_input_is_refused(tmp_path):
    src = real_file("sample_c.las")
    tiles = tmp_path / "tiles"
    tiles.mkdir()
    tile = tiles / "sample_c.las"
    tile.write_bytes(src.read_bytes())
    p = subprocess.run([str(BIN / "skyground"), "classify", "--in", tile, "--out-dir", tiles],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode != 0 and "would overwrite" in p.stderr, p.stderr
    assert tile.read_bytes() == src.read_bytes()


def test_detect_keeps_the_producers_compression(tmp_path):
    """`detect` writes classified.laz for LAZ input and classified.las for LAS
    input; a rerun into the same directory leaves one classified cloud, the
    new one, and `plan` reads whichever is there."""
    import laspy

    las_in, laz_in = real_file("sample_c.las"), real_file("ahn3_delft_2.laz")
    out = tmp_path / "d"
    first = json.loads(run("detect", "--in", las_in, "--out", out, "--json").stdout)
    assert first["outputs"]["classified"] == str(out / "classified.las")
    assert (out / "classified.las").is_file() and not (out / "classified.laz").exists()

    second, plan = detect(tmp_path, "d", laz_in)
    assert second["outputs"]["classified"] == str(out / "classified.laz")
    assert not (out / "classified.las").exists(), "a stale classified.las is left for plan"
    got, src = laspy.read(str(out / "classified.laz")), laspy.read(str(laz_in))
    assert len(got.points) == len(src.points) == second["points"]
    assert (got.gps_time == src.gps_time).all()
    # Compressed: well under the uncompressed records.
    raw = len(src.points) * src.header.point_format.size
    assert (out / "classified.laz").stat().st_size < raw / 3
    assert plan["graph"]["nodes"] > 1000, plan["graph"]

    (out / "classified.laz").unlink()
    p = subprocess.run([str(BIN / "skyground"), "plan", "--in", out],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode != 0 and "no classified.laz or classified.las" in p.stderr, p.stderr


def test_plan_opens_the_streets_under_tree_crowns(tmp_path):
    """On our classes AHN3 Delft 1's street trees are vegetation. `plan` is
    for a robot in the field, which steers round trunks: by default a crown
    blocks only in the vehicle's height band, and the quays under the trees
    join the start's ground. With the planner node's rule (the whole column,
    `canopy_is_obstacle: true` in a params file) `plan` says how much ground
    the start's piece would hold with its own default, which is exactly that."""
    d1 = real_file("ahn3_delft_1.laz")
    out = tmp_path / "d1"
    run("detect", "--in", d1, "--out", out, "--classify", "--json")
    p = subprocess.run([str(BIN / "skyground"), "plan", "--in", out, "--json"],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    band = json.loads(p.stdout)
    assert band["graph_params"]["canopy_is_obstacle"] is False
    assert band["if_crowns_block_only_in_band"] is None
    assert "canopy_is_obstacle" not in p.stderr, p.stderr
    p = plan_with_closed_crowns(tmp_path, out)
    whole = json.loads(p.stdout)
    open_ = whole["if_crowns_block_only_in_band"]
    # Measured: 1,109 nodes with whole columns, 3,702 by default (docs/density.md).
    assert open_["graph"]["nodes"] == band["nodes"] > 2 * whole["nodes"], (whole["nodes"], band["nodes"])
    assert "skyground plan's default" in p.stderr and str(band["nodes"]) in p.stderr, p.stderr
    assert band["reachable_points"] + band["reachable_regions"] > whole["reachable_points"] + whole["reachable_regions"]
    assert band["set_down_node_share"] > whole["set_down_node_share"]


def test_no_crown_hint_where_no_target_is_cut_off(tmp_path):
    """A forest without buildings has no targets: with crowns blocking
    their whole column, `plan` still reports what open crowns would reach
    in the JSON, but does not tell the user to change the vehicle's rule
    for ground no target needs."""
    out = tmp_path / "forest"
    run("detect", "--in", real_file("lidr_mixedconifer.laz"), "--out", out, "--classify", "--json")
    p = plan_with_closed_crowns(tmp_path, out)
    plan = json.loads(p.stdout)
    assert plan["target_points"] + plan["target_regions"] == 0, plan
    # Measured before the hint was limited: 28 nodes, 780 with crowns open.
    assert plan["if_crowns_block_only_in_band"]["graph"]["nodes"] > 1.1 * plan["nodes"], plan
    assert "canopy_is_obstacle" not in p.stderr, p.stderr
