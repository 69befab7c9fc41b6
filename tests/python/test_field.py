"""Field mode (issue 16 part 3): `skyground demo --field` with a robot played by
rclpy (field_robot.py) instead of vehicle_sim. The robot follows /way_point,
publishes /state_estimation and /registered_scan made of the scene's true
building surfaces within its sensor's range and sight; the mission must finish
and the robot's scans must raise coverage against ground truth."""
import json
import subprocess
import time
from pathlib import Path

from conftest import BIN, ROOT
from test_demo import kill_everyone, small_scene, wait_for_log

ROBOT = ROOT / "tests" / "python" / "field_robot.py"
# A free spot of small_scene, south of the two blocks.
START = (40.0, 5.0)


def ground_truth(tmp_path, scene):
    """The scene's building surface samples, as `skyground aerial` writes them."""
    out = tmp_path / "aerial"
    subprocess.run([str(BIN / "skyground"), "aerial", "--scene", str(scene), "--out", str(out)],
                   check=True, capture_output=True, timeout=300)
    return out / "gt_samples.ply"


def test_field_mission_with_an_rclpy_robot_finishes_and_gains(tmp_path, env, spawn):
    scene = small_scene(tmp_path / "small.obj")
    gt = ground_truth(tmp_path, scene)
    robot = spawn(str(ROBOT), "--gt", gt, "--start", *START)
    assert robot.json_lines(1, timeout=60)[0]["event"] == "ready"
    out = tmp_path / "out"
    t0 = time.time()
    p = subprocess.run([str(BIN / "skyground"), "demo", "--field", "--scene", str(scene), "--out", str(out),
                        "--timeout", "300", "--robot-timeout", "60"],
                       capture_output=True, text=True, timeout=400, env=env)
    wall = time.time() - t0
    robot.stop()
    events = [json.loads(line) for line in (robot.p.stdout.read() or b"").splitlines() if line.strip()]
    bridge = out / "robot_bridge.log"
    # What a failure needs to be read: did the robot hear its way-points, did the bridge see a reader.
    seen = (f"\nrobot events: {len(events)}, the last: {events[-5:]}\nrobot stderr: {Path(robot.log_path).read_text(errors='replace')[-1500:]}"
            f"\nrobot_bridge.log: {bridge.read_text(errors='replace')[-3000:] if bridge.exists() else '(none)'}")
    assert p.returncode == 0, p.stderr[-4000:] + seen
    assert "robot found on /state_estimation" in p.stderr
    report = json.loads((out / "report.json").read_text())
    print(f"\nfield mode: coverage {report['coverage_before']:.4f} -> {report['coverage_after']:.4f}, "
          f"mean GT dist {report['mean_gt_dist_before']:.3f} -> {report['mean_gt_dist_after']:.3f} m, "
          f"{report['path_length_m']:.0f} m driven, {report['rounds']} rounds, "
          f"{report['targets_reached']} reached / {report['targets_given_up']} given up / "
          f"{report['targets_unreachable']} unreachable, "
          f"{report['sim_time_s']:.0f} robot s, {wall:.0f} s wall")
    assert report["finished"] is True and report["mode"] == "field"
    assert "small.obj" in report["ground_truth"]
    assert sum(e["event"] == "way_point" for e in events) >= 2, seen
    assert report["path_length_m"] > 10 and report["sim_time_s"] > 0, seen
    assert report["rounds"] >= 1 and report["targets_reached"] >= 1, seen
    assert report["coverage_after"] > report["coverage_before"] + 0.02
    assert report["mean_gt_dist_after"] < report["mean_gt_dist_before"]
    # No vehicle_sim: the robot drove, the bridge told the planners.
    assert not (out / "vehicle_sim.log").exists()
    log = bridge.read_text(errors="replace")
    assert "arrived at" in log
    assert "/way_point: 1 subscriber(s) matched" in log, log[-2000:]


def test_a_field_mission_whose_laptop_died_resumes_with_the_robot_where_it_is(tmp_path, env, spawn):
    """Issue 50 part 4 in field mode: every skyground process killed mid-round
    (the laptop died; the robot, a process of its own, drives on and stops at
    its last way-point), then `demo --resume DIR`: the planner goes on with the
    interrupted round's remaining stops from where the robot now is, and the
    mission finishes with the robot's scans of both runs."""
    scene = small_scene(tmp_path / "small.obj")
    gt = ground_truth(tmp_path, scene)
    robot = spawn(str(ROBOT), "--gt", gt, "--start", *START)
    assert robot.json_lines(1, timeout=60)[0]["event"] == "ready"
    out = tmp_path / "out"
    argv = [str(BIN / "skyground"), "demo", "--field", "--scene", str(scene), "--out", str(out),
            "--timeout", "300", "--robot-timeout", "60"]
    proc = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)
    try:
        assert wait_for_log(out / "global_planner.log", "round 1: route over", proc, 240)
        time.sleep(2)
    finally:
        kill_everyone(proc)
    p = subprocess.run(argv[:2] + ["--resume", str(out)], capture_output=True, text=True, timeout=400, env=env)
    robot.stop()
    assert p.returncode == 0, p.stderr[-4000:]
    assert "resuming:" in p.stderr
    report = json.loads((out / "report.json").read_text())
    print(f"\nfield mode killed and resumed: coverage {report['coverage_before']:.4f} -> "
          f"{report['coverage_after']:.4f}, {report['rounds']} rounds, {report['targets_reached']} stops, "
          f"{report['path_length_m']:.0f} m")
    assert report["finished"] is True and report["mode"] == "field" and report["runs"] == 2
    assert report["coverage_after"] > report["coverage_before"] + 0.02
    # Killed 2 s into round 1's route: the resumed planner finishes that round.
    log = (out / "global_planner.log").read_text(errors="replace")
    if "going on with the round it was driving" in p.stderr:
        assert "going on with the kept round" in log, log[-2000:]


def test_field_mode_without_a_robot_stops_with_a_clear_error(tmp_path, env):
    scene = small_scene(tmp_path / "small.obj")
    out = tmp_path / "out"
    p = subprocess.run([str(BIN / "skyground"), "demo", "--field", "--scene", str(scene), "--out", str(out),
                        "--robot-timeout", "5"],
                       capture_output=True, text=True, timeout=200, env=env)
    assert p.returncode != 0
    assert "no /state_estimation from a robot within 5 s" in p.stderr, p.stderr[-3000:]
    report = json.loads((out / "report.json").read_text())
    assert report["finished"] is False and report["path_length_m"] == 0
