"""Reading the farm CLI's progress, and a FarmRun driven by a stand-in for the CLI (a
script that prints what `farm submit --watch` prints)."""

import stat
import time

import pytest
from sources import load

farmcli = load("photonfarm_blender/farmcli.py")


@pytest.mark.parametrize("line, fraction", [
    ("job j-1: Render tiles 12/20 tiles (60%), elapsed 3s, ETA 1s", 0.6),
    ("job j-1: queued, elapsed 0s", None),
    ("render 3/4 [#########-----]  21/48 tiles   43%  elapsed 0:04  ETA 0:05", 0.43),
    ("job j-1: succeeded (emit 2/2, render 20/20), took 5.5s", None),
])
def test_progress_fraction(line, fraction):
    assert farmcli.progress_fraction(line) == fraction


def _fake_farm(tmp_path, body):
    path = tmp_path / "farm"
    path.write_text("#!/bin/sh\n" + body)
    path.chmod(path.stat().st_mode | stat.S_IEXEC)
    return str(path)


def test_farm_run_reads_the_job_id_and_progress(tmp_path):
    farm = _fake_farm(tmp_path, 'test "$1 $3" = "submit --watch" || exit 9\n'
                                'test "$FARM_TOKEN" = secret || exit 8\n'
                                'echo j-42\necho "job j-42: Render tiles 1/4 tiles (25%)"\n'
                                'echo "job j-42: succeeded, took 1s"\n')
    run = farmcli.FarmRun(farm, "scene.json", coordinator="127.0.0.1:1", token="secret")
    deadline = time.monotonic() + 10
    status = None
    while status is None and time.monotonic() < deadline:
        status = run.poll()
        time.sleep(0.01)
    assert status == 0
    assert run.job_id == "j-42"
    assert run.fraction == 0.25
    assert run.last_line == "job j-42: succeeded, took 1s"


def test_a_failed_submission_says_what_the_cli_said(tmp_path):
    farm = _fake_farm(tmp_path, 'echo "farm: scene.json: shapes[0].sphere.radius: must be > 0" >&2\nexit 2\n')
    run = farmcli.FarmRun(farm, "scene.json")
    status = run.wait()
    assert status == 2
    assert "shapes[0].sphere.radius" in str(run.failure(status))
