"""The scale-out API that docs/scale-out.md describes: what /metrics tells a scaler of worker
processes (caustic_queued_tasks, expired leases included; caustic_workers), and re-queueing a
failed job (POST /api/jobs/{id}/requeue)."""

import re
import time

import pytest

from conftest import UNKNOWN_ID, assert_problem, submit_ok, tiny_scene
from farm import Worker

pytestmark = pytest.mark.scaleout


def metric(server, name):
    r = server.get("/metrics")
    assert r.status_code == 200, r.text
    m = re.search(rf"^{name} (\S+)$", r.text, re.MULTILINE)
    assert m, f"no {name} in /metrics:\n{r.text}"
    return float(m.group(1))


def wait_for(check, what, deadline=60):
    end = time.monotonic() + deadline
    while not check():
        assert time.monotonic() < end, f"timed out waiting for {what}"
        time.sleep(0.1)


def test_queued_tasks_and_workers(farm, caustic_bin, tmp_path):
    api, _ = farm(workers=0)
    assert metric(api, "caustic_queued_tasks") == 0
    assert metric(api, "caustic_workers") == 0
    # 16 passes in tasks of 4, and 6 in tasks of 5 (the last one short): 4 + 2 tasks.
    small = {"scene": tiny_scene(width=16, height=16), "settings": {"spp": 16, "spp_per_pass": 1}}
    first = submit_ok(api, {**small, "task_passes": 4})
    second = submit_ok(api, {**small, "settings": {"spp": 6, "spp_per_pass": 1},
                             "task_passes": 5, "priority": 7})
    assert metric(api, "caustic_queued_tasks") == 6
    assert metric(api, "caustic_queue_depth") == 2
    # A cancelled job's tasks wait for nobody.
    assert api.post(f"/api/jobs/{first['id']}/cancel").status_code == 202
    assert metric(api, "caustic_queued_tasks") == 2

    worker = Worker(caustic_bin, api.store, str(tmp_path), "--threads", "1").start()
    try:
        done = api.wait(second["id"], ("succeeded", "failed"), 120)
        assert done["state"] == "succeeded", done
        assert metric(api, "caustic_queued_tasks") == 0
        wait_for(lambda: metric(api, "caustic_workers") == 1, "caustic_workers 1")
    finally:
        worker.stop()
    wait_for(lambda: metric(api, "caustic_workers") == 0, "caustic_workers 0 once it stopped")


def test_a_killed_workers_task_counts_as_queued_once_its_lease_expires(farm, caustic_bin,
                                                                       tmp_path):
    api, _ = farm(workers=0)
    # Two tasks of one long pass each: the worker is still rendering the first when it is killed.
    job = submit_ok(api, {"scene": tiny_scene(width=128, height=128),
                          "settings": {"spp": 2048, "spp_per_pass": 1024}, "task_passes": 1})
    worker = Worker(caustic_bin, api.store, str(tmp_path), "--threads", "1",
                    "--lease-seconds", "1").start()
    try:
        wait_for(lambda: any(w["task"] for w in api.get("/api/workers").json()["workers"]),
                 "the worker's task")
        assert metric(api, "caustic_queued_tasks") == 1
    finally:
        worker.kill()
    # Nobody claims again, so the task stays running in the table with its lease expired.
    time.sleep(1.5)
    assert metric(api, "caustic_queued_tasks") == 2
    assert api.job(job["id"])["state"] == "running"


def test_a_requeued_job_keeps_its_tasks_and_gets_its_time_limit_again(farm, caustic_bin, tmp_path):
    api, [broken] = farm(workers=1, worker_args=("--fail-every-task", "--block-after-failures", "1",
                                                 "--fail-after-workers", "1"))
    body = {"scene": tiny_scene(width=16, height=16), "task_passes": 2,
            "settings": {"spp": 8, "spp_per_pass": 1, "time_limit": 2}}
    job = submit_ok(api, body)
    failed = api.wait(job["id"], ("failed", "succeeded", "cancelled"), 60)
    assert failed["state"] == "failed" and "its tasks failed on 1 workers" in failed["error"], failed
    broken.stop()
    assert_problem(api.post(f"/api/jobs/{UNKNOWN_ID}/requeue"), 404)
    # Past its time limit counted from its first start: the limit counts again from the re-queue.
    time.sleep(2.5)
    worker = Worker(caustic_bin, api.store, str(tmp_path), "--threads", "1").start()
    try:
        r = api.post(f"/api/jobs/{job['id']}/requeue")
        assert r.status_code == 202, r.text
        assert r.json()["state"] == "queued" and r.json()["error"] is None, r.json()
        done = api.wait(job["id"], ("succeeded", "failed", "cancelled"), 120)
        assert done["state"] == "succeeded", done
        assert done["passes_done"] == 8 and done["stats"]["stop_reason"] == "spp", done
        assert done["stats"]["tasks"] == 4, done
        assert_problem(api.post(f"/api/jobs/{job['id']}/requeue"), 409)
    finally:
        worker.stop()
