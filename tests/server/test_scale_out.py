"""Scale-out on PostgreSQL (README "Scale-out"; server/store/task.h): one API process and worker
processes render split jobs whose images are bit-identical to a single SQLite process's."""

import pytest

from conftest import submit_ok, tiny_scene

pytestmark = pytest.mark.scaleout


def rendered(server, body, deadline=120):
    """Submits `body`, waits for it to succeed, returns (job, image.exr bytes)."""
    job = submit_ok(server, body)
    done = server.wait(job["id"], ("succeeded", "failed", "cancelled"), deadline)
    assert done["state"] == "succeeded", done
    r = server.get(f"/api/jobs/{job['id']}/image.exr")
    assert r.status_code == 200, r.text
    return done, r.content


def test_a_split_path_traced_job_is_bit_identical_to_one_process(farm, start_server):
    api, _ = farm(workers=3)
    single = start_server("--threads", "1")
    body = {"scene": tiny_scene(width=48, height=48), "settings": {"spp": 64, "spp_per_pass": 4}}
    job, split = rendered(api, {**body, "task_passes": 3})
    assert job["passes_done"] == 16 and job["stats"]["tasks"] == 6, job
    _, whole = rendered(single, body)
    assert split == whole
