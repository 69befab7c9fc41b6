"""`skyground demo` end to end on the reference scene (a short ring): every node
a process, the mission finishes, coverage rises, the bag decodes."""
import json
import subprocess

from mcap_ros2.reader import read_ros2_messages

from conftest import BIN


def test_short_demo_mission_gains_coverage_and_records_a_bag(tmp_path, env):
    p = subprocess.run([str(BIN / "skyground"), "demo", "--out", str(tmp_path), "--way-points", "3",
                        "--radius", "30", "--time-factor", "20", "--timeout", "240"],
                       capture_output=True, text=True, timeout=400, env=env)
    assert p.returncode == 0, p.stderr[-3000:]
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["coverage_after"] > report["coverage_before"] > 0.75
    assert report["mean_gt_dist_after"] < report["mean_gt_dist_before"]
    assert report["reached"] + report["blocked"] == report["way_points"] == 6
    assert report["path_length_m"] > 0 and report["sim_time_s"] > 0
    topics = {}
    for m in read_ros2_messages(str(tmp_path / "mission.mcap")):
        topics[m.channel.topic] = topics.get(m.channel.topic, 0) + 1
    assert topics.get("/aerial_cloud", 0) >= 1 and topics.get("/state_estimation", 0) > 10
    assert topics.get("/way_point", 0) >= 1
