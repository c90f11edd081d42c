"""The SDK against a real coordinator and worker (conftest.py): issue 16's acceptance 2."""

from __future__ import annotations

import copy
import hashlib
import json
import time

import grpc
import numpy as np
import pytest
from renderfarm.v1 import blob_pb2, job_pb2

import photonfarm
from conftest import CLIENT_TOKEN, REPO

SCENE = REPO / "scenes" / "test-small.json"


@pytest.fixture
def client(farm):
    with photonfarm.Client(farm.address, token=CLIENT_TOKEN, tls=str(farm.ca_file)) as c:
        yield c


def small(scene: dict) -> dict:
    """The scene at 16x16 with small photon maps: a job of a second or two."""
    scene = copy.deepcopy(scene)
    scene["film"] = {"width": 16, "height": 16, "tileSize": 16}
    scene["sampling"]["samplesPerPixel"] = 1
    scene["photons"] = {"globalPhotons": 2000, "photonsPerShard": 2000}
    return scene


def job_count(client: photonfarm.Client) -> int:
    return len(client.jobs.ListJobs(job_pb2.ListJobsRequest(page_size=1000), timeout=10).jobs)


def test_submit_watch_fetch_gives_the_indirect_layer_as_an_array_of_the_film(client):
    film = json.loads(SCENE.read_text())["film"]
    job = client.submit(str(SCENE))  # uploads meshes/octahedron.obj, relative to the file

    events = list(client.watch(job.id))
    assert events[0].kind == job_pb2.JOB_EVENT_KIND_SNAPSHOT
    assert events[-1].ended and events[-1].job.state == job_pb2.JOB_STATE_SUCCEEDED, events[-1].job.error
    assert not any(e.ended for e in events[:-1])
    tasks = {e.task.id for e in events if e.kind == job_pb2.JOB_EVENT_KIND_TASK_UPDATED}
    assert len(tasks) >= 12, "the 64x48 film in 16-pixel tiles has 12 render tasks besides the others"

    image = client.fetch(job.id)
    indirect = image.layers["indirect"]
    assert indirect.shape == (film["height"], film["width"], 3) and indirect.dtype == np.float32
    assert (image.width, image.height) == (film["width"], film["height"])
    assert np.isfinite(indirect).all() and (indirect >= 0).all()
    assert indirect.mean() > 0, "the floor is lit by light bounced off the balls"
    # The renderer writes the beauty as the sum of the light layers: layers read into the
    # wrong names, transposed or in the wrong component order would break it.
    light = image.layers["direct"] + indirect + image.layers["caustic"] + image.layers["volume"]
    np.testing.assert_allclose(image.layers["beauty"][..., :3], light, rtol=1e-5, atol=1e-6)
    assert image.layers["depth"].shape == (film["height"], film["width"])

    report = client.report(job.id)
    assert (report.job_id, report.name, report.state) == (job.id, "test-small", "succeeded")
    assert len(report.rounds) == 1 and report.rounds[0].samples_per_pixel == 8
    assert report.rounds[0].photons > 0 and report.rounds[0].elapsed_seconds > 0


def test_report_of_a_two_round_job_carries_the_estimated_error_with_its_bias_and_interval(client):
    scene = small(json.loads(SCENE.read_text()))
    scene["progressive"] = {"maxRounds": 2}
    job = client.submit(scene, asset_root=REPO / "scenes")
    last = list(client.watch(job.id))[-1]
    assert last.ended and last.job.state == job_pb2.JOB_STATE_SUCCEEDED, last.job.error

    first, second = client.report(job.id).rounds
    # One round has no spread between rounds to estimate from: nothing is said.
    assert (first.error_estimate, first.error_estimate_bias, first.error_estimate_low,
            first.error_estimate_high) == (None, None, None, None)
    assert second.error_estimate is not None and second.error_estimate > 0
    assert 0 <= second.error_estimate_bias <= second.error_estimate, "the bias is a part of the estimate"
    assert second.error_estimate_low <= second.error_estimate <= second.error_estimate_high


def test_cancel_requeue_and_delete_a_job_and_retry_refuses_a_task_that_did_not_fail(client):
    scene = small(json.loads(SCENE.read_text()))
    # A job of a second or more (several phases): the cancel, a few ms after the submit,
    # finds it queued or running.
    scene["sampling"]["samplesPerPixel"] = 64
    job = client.submit(scene, asset_root=REPO / "scenes")
    assert client.cancel(job.id).state == job_pb2.JOB_STATE_CANCELLED
    with pytest.raises(photonfarm.FarmError) as e:
        client.cancel(job.id)
    assert e.value.code == grpc.StatusCode.FAILED_PRECONDITION

    assert client.requeue(job.id).state in (job_pb2.JOB_STATE_QUEUED, job_pb2.JOB_STATE_RUNNING)
    events = list(client.watch(job.id))
    assert events[-1].job.state == job_pb2.JOB_STATE_SUCCEEDED, events[-1].job.error
    with pytest.raises(photonfarm.FarmError) as e:
        client.requeue(job.id)
    assert e.value.code == grpc.StatusCode.FAILED_PRECONDITION

    tasks = client.jobs.ListTasks(job_pb2.ListTasksRequest(job_id=job.id, page_size=1), timeout=10).tasks
    with pytest.raises(photonfarm.FarmError) as e:
        client.retry(tasks[0].id)
    assert e.value.code == grpc.StatusCode.FAILED_PRECONDITION

    assert client.delete(job.id).id == job.id
    with pytest.raises(photonfarm.FarmError) as e:
        client.get_job(job.id)
    assert e.value.code == grpc.StatusCode.NOT_FOUND


def test_a_dict_scene_takes_a_mesh_from_bytes(client):
    scene = small(json.loads(SCENE.read_text()))
    scene["shapes"][3]["mesh"]["path"] = "made/in-memory.obj"  # no such file on disk
    mesh = (REPO / "scenes" / "meshes" / "octahedron.obj").read_bytes() + b"# made in memory\n"
    job = client.submit(scene, {"made/in-memory.obj": mesh})
    assert list(client.watch(job.id))[-1].job.state == job_pb2.JOB_STATE_SUCCEEDED
    digest = "sha256:" + hashlib.sha256(mesh).hexdigest()
    info = client.blobs.GetBlobInfo(blob_pb2.GetBlobInfoRequest(digest=digest), timeout=10)
    assert info.size_bytes == len(mesh)


def test_a_refused_field_raises_invalid_argument_naming_it_and_makes_no_job(client):
    scene = small(json.loads(SCENE.read_text()))
    scene["shapes"][1]["sphere"]["radius"] = -1
    before = job_count(client)
    with pytest.raises(photonfarm.FarmError) as e:
        client.submit(scene, asset_root=REPO / "scenes")
    assert e.value.code == grpc.StatusCode.INVALID_ARGUMENT
    assert e.value.field == "shapes[1].sphere.radius" and "-1" in e.value.message
    assert job_count(client) == before


def test_a_missing_mesh_file_is_refused_naming_the_field_before_any_job(client, tmp_path):
    scene = small(json.loads(SCENE.read_text()))
    scene["shapes"][3]["mesh"]["path"] = "meshes/missing.obj"
    (tmp_path / "scene.json").write_text(json.dumps(scene))
    before = job_count(client)
    with pytest.raises(photonfarm.FarmError) as e:
        client.submit(tmp_path / "scene.json")
    assert e.value.code == grpc.StatusCode.INVALID_ARGUMENT and e.value.field == "shapes[3].mesh.path"
    assert "meshes/missing.obj" in e.value.message and "No such file" in e.value.message
    assert job_count(client) == before


def test_a_mesh_the_coordinator_refuses_names_the_field_and_the_file(client):
    scene = small(json.loads(SCENE.read_text()))
    scene["shapes"][3]["mesh"]["path"] = "broken.obj"
    with pytest.raises(photonfarm.FarmError) as e:
        client.submit(scene, {"broken.obj": b"v 0 0 0\nf 1 2 3\n"})
    assert e.value.code == grpc.StatusCode.INVALID_ARGUMENT
    assert e.value.field.startswith("shapes[3].mesh") and "broken.obj" in str(e.value)


def test_without_a_token_the_error_says_to_give_one(farm):
    with photonfarm.Client(farm.address, token="", tls=str(farm.ca_file)) as c:
        with pytest.raises(photonfarm.FarmError) as e:
            c.get_job("j-none")
    assert e.value.code == grpc.StatusCode.UNAUTHENTICATED
    assert "token=" in e.value.hint and "$FARM_TOKEN" in e.value.hint


def test_with_no_coordinator_the_error_says_to_start_one_within_5_s(unused_address):
    start = time.monotonic()
    with photonfarm.Client(unused_address, token=CLIENT_TOKEN) as c:
        with pytest.raises(photonfarm.FarmError) as e:
            c.submit(small(json.loads(SCENE.read_text())), asset_root=REPO / "scenes")
    assert time.monotonic() - start < 5
    assert e.value.code == grpc.StatusCode.UNAVAILABLE
    assert unused_address in e.value.hint and "farm coordinator" in e.value.hint


def test_a_list_of_replicas_goes_on_through_the_one_that_answers(farm, unused_address):
    # A dead replica first: round_robin leaves it out and every call reaches the live one.
    with photonfarm.Client(f"{unused_address},{farm.address}", token=CLIENT_TOKEN, tls=str(farm.ca_file)) as c:
        for _ in range(6):
            c.jobs.ListJobs(job_pb2.ListJobsRequest(page_size=1), timeout=10)


def test_plaintext_to_a_tls_coordinator_fails_as_unavailable(farm):
    with photonfarm.Client(farm.address, token=CLIENT_TOKEN, tls=False) as c:
        with pytest.raises(photonfarm.FarmError) as e:
            c.get_job("j-none")
    assert e.value.code == grpc.StatusCode.UNAVAILABLE


def test_the_cli_variables_are_the_defaults(farm, monkeypatch):
    monkeypatch.setenv("FARM_COORDINATOR", farm.address)
    monkeypatch.setenv("FARM_TOKEN", CLIENT_TOKEN)
    monkeypatch.setenv("FARM_TLS_CA", str(farm.ca_file))
    with photonfarm.Client() as c:
        assert c.address == farm.address
        c.jobs.ListJobs(job_pb2.ListJobsRequest(page_size=1), timeout=10)  # the raw stub carries the token
