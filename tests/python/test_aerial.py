"""`skyground aerial`: the airborne prior of the reference scene, its LAS file
as laspy reads it, and its completeness in the paper's range."""
import json
import subprocess

import numpy as np

from conftest import BIN


def run_aerial(scene, out):
    p = subprocess.run([str(BIN / "skyground"), "aerial", "--scene", scene, "--out", str(out), "--json"],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def test_reference_prior_is_75_to_92_percent_complete_with_gaps_where_flights_leave_them(tmp_path):
    import laspy

    s = run_aerial("reference", tmp_path)
    assert 12 <= s["buildings"] <= 20
    assert 0.75 <= s["completeness"] <= 0.92, s["completeness"]
    assert s["completeness_roofs"] > s["completeness_walls"]
    gaps = s["where_the_gaps_are"]
    assert gaps["undersides"]["completeness"] < 0.2, "the hollow base must stay hidden from the air"
    assert gaps["walls_near_trees"]["completeness"] < gaps["other_walls"]["completeness"]
    las = laspy.read(str(tmp_path / "aerial.las"))
    assert las.header.version.major == 1 and las.header.version.minor == 4
    assert len(las.points) == s["points"]
    assert set(np.unique(np.asarray(las.classification))) <= {2, 5, 6}
    building = np.asarray(las["building"])
    cls = np.asarray(las.classification)
    assert (building[cls == 6] > 0).all() and (building[cls != 6] == 0).all()
    assert len(np.unique(building[cls == 6])) == s["buildings"]

