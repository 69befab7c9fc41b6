"""`skyground demo --prior` (issue 16 part 2): a real aerial survey (AHN3 Delft)
as the prior, with its real city model (delft.json) as the world the vehicle
drives in and the ground truth; and the clear errors when the two do not fit
together. Needs ../shared/data/real (SKIPPED without it)."""
import json
import subprocess

from conftest import BIN, real_file


def run_demo(tmp_path, env, *args, timeout):
    out = tmp_path / "out"
    argv = [str(BIN / "skyground"), "demo", "--out", str(out), "--platforms", "ground", *map(str, args)]
    return out, subprocess.run(argv, capture_output=True, text=True, timeout=timeout, env=env)


def test_the_mission_on_ahn3_delft_2_finishes_and_gains(tmp_path, env):
    prior, model = real_file("ahn3_delft_2.laz"), real_file("delft.json")
    out, p = run_demo(tmp_path, env, "--scene", model, "--prior", prior, timeout=3000)
    assert p.returncode == 0, p.stderr[-4000:]
    assert "cropping the city model to the prior's extent" in p.stderr, p.stderr[-4000:]
    report = json.loads((out / "report.json").read_text())
    print(f"\ncoverage {report['coverage_before']:.4f} -> {report['coverage_after']:.4f}, "
          f"walls {report['walls_before']:.4f} -> {report['walls_after']:.4f}, "
          f"{report['rounds']} rounds, {report['path_length_m']:.0f} m, {report['wall_time_s']:.0f} s wall")
    assert report["finished"] is True
    assert report["prior"] == str(prior)
    assert report["coverage_after"] > report["coverage_before"]
    assert report["rounds"] >= 1 and report["path_length_m"] > 10
    # A canal cuts the tile's northern third off the start's ground: the
    # planner asks for set-downs there and vehicle_sim carries the vehicle.
    assert report["set_downs"] >= 1, p.stderr[-4000:]
    carried = (out / "vehicle_sim.log").read_text().count("set down at (")
    assert carried >= report["set_downs"], carried
    # The mission is about the area the prior covers, not the whole model.
    assert 0 < report["crop"]["buildings_kept"] < report["crop"]["buildings_total"] == 160
    assert "| prior | " + str(prior) in (out / "report.md").read_text()
    # AHN3 names no CRS: taken to be the model's (EPSG:7415, RD New + NAP),
    # and written so, in RD coordinates (Delft: x ≈ 85 km, y ≈ 447 km).
    import laspy
    for name in ["aerial.laz", "resampled.laz"]:
        hdr = laspy.read(str(out / name)).header
        crs = hdr.parse_crs()
        assert crs is not None and "Amersfoort / RD New" in crs.name, (name, crs)
        assert 80_000 < hdr.mins[0] < hdr.maxs[0] < 90_000, (name, hdr.mins, hdr.maxs)
        assert 440_000 < hdr.mins[1] < hdr.maxs[1] < 450_000, (name, hdr.mins, hdr.maxs)


def test_a_prior_in_another_crs_is_refused(tmp_path, env):
    # IGN Montpellier states EPSG:2154 (Lambert-93); delft.json is RD New + NAP.
    prior, model = real_file("ign_montpellier_150x100m.laz"), real_file("delft.json")
    _, p = run_demo(tmp_path, env, "--scene", model, "--prior", prior, timeout=300)
    assert p.returncode != 0
    assert "horizontal CRSs differ (EPSG:2154 vs EPSG:28992)" in p.stderr, p.stderr[-2000:]


def test_a_prior_elsewhere_is_refused(tmp_path, env):
    # AHN3 states no CRS (taken as the model's), but Zurich is 700 km away.
    prior, model = real_file("ahn3_delft_2.laz"), real_file("zurich_subset_lod2.json")
    _, p = run_demo(tmp_path, env, "--scene", model, "--prior", prior, timeout=300)
    assert p.returncode != 0
    assert "do not overlap" in p.stderr, p.stderr[-2000:]
