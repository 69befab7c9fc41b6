"""Any city layout starts (issue 49, part 4): the demo on real Zurich LoD2
buildings (../shared/data/real/zurich_subset_lod2.json) moved into layouts
made at test time (tests/python/city_layouts.py): four clusters ~500 m apart
without terrain, a single building, the spread layout in a local frame
without a CRS. Each must start its vehicle and run until the time limit;
three buildings 500 m apart must also run to the end with coverage after
≥ 95 % (issue 49's closing note); the library side (holes in the ground,
another datum, impossible cases) is core/tests/layouts.rs."""
import json
import os
import subprocess

import pytest

import city_layouts
from conftest import BIN, REAL, _domains


@pytest.mark.parametrize("layout", ["spread", "single", "local"])
def test_the_demo_starts_on_a_city_layout(tmp_path, layout):
    if not (REAL / city_layouts.ZURICH).is_file():
        pytest.skip(f"SKIPPED: {REAL / city_layouts.ZURICH} not found")
    scene = city_layouts.write(layout, tmp_path / f"{layout}.city.json", real=REAL)
    out = tmp_path / "out"
    env = dict(os.environ, ROS_DOMAIN_ID=str(next(_domains)))
    env.pop("RUST_LOG", None)
    p = subprocess.run([str(BIN / "skyground"), "demo", "--scene", str(scene), "--out", str(out),
                        "--crop", "none", "--platforms", "ground", "--timeout", "40"],
                       capture_output=True, text=True, timeout=400, env=env)
    # Finished, or stopped by the test's short --timeout (exit 1, report written).
    assert p.returncode == 0 or "(--timeout)" in p.stderr, p.stderr[-3000:]
    assert "no start" not in p.stderr, p.stderr[-3000:]
    report = json.loads((out / "report.json").read_text())
    assert report["coverage_before"] > 0.0, report
    # The simulator found its start and drove or scanned from it.
    sim_log = (out / "vehicle_sim.log").read_text()
    assert "ERROR" not in sim_log, sim_log[-2000:]


def test_the_demo_finishes_on_buildings_500_m_apart(tmp_path):
    """Issue 49 must-show: a CityJSON model with buildings 500 m apart and no
    terrain; the demo runs to its stop rule (exit 0, no --timeout) and the
    scans bring coverage to at least 95 %."""
    if not (REAL / city_layouts.ZURICH).is_file():
        pytest.skip(f"SKIPPED: {REAL / city_layouts.ZURICH} not found")
    scene = city_layouts.write("far", tmp_path / "far.city.json", real=REAL)
    out = tmp_path / "out"
    env = dict(os.environ, ROS_DOMAIN_ID=str(next(_domains)))
    env.pop("RUST_LOG", None)
    p = subprocess.run([str(BIN / "skyground"), "demo", "--scene", str(scene), "--out", str(out),
                        "--crop", "none", "--platforms", "ground"],
                       capture_output=True, text=True, timeout=900, env=env)
    assert p.returncode == 0, p.stderr[-3000:]
    report = json.loads((out / "report.json").read_text())
    assert report["finished"], report["ended_because"]
    # Each building reached: the vehicle drove the two ~480 m gaps between them.
    assert report["path_length_m"] > 900.0, report
    assert report["coverage_after"] >= 0.95, report
    assert report["coverage_after"] > report["coverage_before"], report
