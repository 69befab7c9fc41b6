"""Commands that need an outside tool (the rclpy venv) say which and how to
get it, before they start anything."""
import subprocess

from conftest import BIN


def test_bench_transport_without_the_venv_says_how_to_make_it(tmp_path, env):
    p = subprocess.run([str(BIN / "skyground"), "bench", "transport", "--python", str(tmp_path / "no" / "python"),
                        "--points", "10", "--repeats", "1"],
                       capture_output=True, text=True, timeout=120, env=env, cwd=tmp_path)
    assert p.returncode != 0
    assert "needs Python with rclpy" in p.stderr, p.stderr
    assert "tests/setup_venv.sh" in p.stderr, p.stderr
    assert "panicked" not in p.stderr, p.stderr


def test_bench_transport_without_its_peer_script_says_where_to_run_from(tmp_path, env):
    import sys
    p = subprocess.run([str(BIN / "skyground"), "bench", "transport", "--python", sys.executable,
                        "--points", "10", "--repeats", "1"],
                       capture_output=True, text=True, timeout=120, env=env, cwd=tmp_path)
    assert p.returncode != 0
    assert "tests/python/peer_cloud.py" in p.stderr and "--peer" in p.stderr, p.stderr
