"""The harness's own respawn: a process that exits with EXIT_STUCK (a node whose
DDS creation deadlocked) is started again, as ros2 launch's respawn=True
does; any other exit is reported, not hidden."""
import pytest

from conftest import EXIT_STUCK

STUCK_ONCE = """
import json, os, sys, time
marker = sys.argv[1]
if not os.path.exists(marker):
    open(marker, "w").close()
    print('{"cut sh', end="", flush=True)
    sys.exit(int(sys.argv[2]))
print(json.dumps({"started": True}), flush=True)
time.sleep(60)
"""

ALWAYS = """
import sys
sys.exit(int(sys.argv[1]))
"""


def script(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_a_process_stuck_once_is_started_again_and_its_output_read(spawn, tmp_path):
    p = spawn(script(tmp_path, "stuck_once.py", STUCK_ONCE), tmp_path / "marker", EXIT_STUCK)
    assert p.json_lines(1, timeout=30) == [{"started": True}]
    assert p.restarts == 1
    assert f"[harness] exited {EXIT_STUCK}; starting it again (1)" in p.stderr()


def test_a_process_always_stuck_is_given_up_after_its_respawns(spawn, tmp_path):
    p = spawn(script(tmp_path, "always.py", ALWAYS), EXIT_STUCK)
    with pytest.raises(RuntimeError, match=f"exited {EXIT_STUCK}"):
        p.json_lines(1, timeout=30)
    assert p.restarts == 2


@pytest.mark.parametrize("rc", [0, 1, 3])
def test_any_other_exit_is_not_started_again(spawn, tmp_path, rc):
    p = spawn(script(tmp_path, "stuck_once.py", STUCK_ONCE), tmp_path / "marker", rc)
    with pytest.raises(RuntimeError, match=f"exited {rc}"):
        p.json_lines(1, timeout=30)
    assert p.restarts == 0
