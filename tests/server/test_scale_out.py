"""Scale-out on PostgreSQL (docs/scale-out.md; server/store/task.h): one API process and worker
processes render split jobs whose images are bit-identical to a single SQLite process's; jobs are
claimed by priority, workers are listed, a failing worker is blocked from a job, a cancelled job is
re-queued with the passes it has, and event streams follow what the workers render.

Scenes are small (48x48) so that the module runs in about a minute on 2 cores; a "long" job here
renders for a few seconds, long enough to be seen running."""

import concurrent.futures
import math
import re
import time

import pytest

from conftest import UNKNOWN_ID, assert_problem, png_info, sse_events, submit_ok, tiny_scene

pytestmark = pytest.mark.scaleout

SCENE = tiny_scene(width=48, height=48)
ENDED = ("succeeded", "failed", "cancelled")


@pytest.fixture(scope="module")
def single(start_server):
    """A SQLite `caustic serve` rendering each job in one process: the reference images."""
    s = start_server("--threads", "1")
    yield s
    s.stop()


def rendered(server, body, deadline=120):
    """Submits `body`, waits for it to succeed, returns (job, (image.exr, image.png) bytes)."""
    job = submit_ok(server, body)
    done = server.wait(job["id"], ENDED, deadline)
    assert done["state"] == "succeeded", done
    return done, images(server, job["id"])


def images(server, job_id):
    files = []
    for name in ("image.exr", "image.png"):
        r = server.get(f"/api/jobs/{job_id}/{name}")
        assert r.status_code == 200, r.text
        files.append(r.content)
    return tuple(files)


def long_body(passes=48, spp_per_pass=256, task_passes=8):
    """A job of `passes` passes of about 0.2 s each on one thread."""
    return {"scene": SCENE, "settings": {"spp": passes * spp_per_pass,
                                         "spp_per_pass": spp_per_pass}, "task_passes": task_passes}


def workers_of(api):
    r = api.get("/api/workers")
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["store"] == "postgresql", body
    return body["workers"]


def worker_row(api, worker):
    """The rows of GET /api/workers of one `caustic worker` process (its id holds the pid)."""
    return [w for w in workers_of(api) if f"-{worker.proc.pid}-" in w["id"]]


def wait_for(check, what, deadline=30):
    """Calls check() until it returns something true; returns that."""
    end = time.monotonic() + deadline
    while True:
        value = check()
        if value:
            return value
        assert time.monotonic() < end, f"{what}: not in {deadline} s"
        time.sleep(0.05)


def wait_workers(api, n):
    return wait_for(lambda: len(workers_of(api)) == n and workers_of(api), f"{n} workers listed")


# 1. Split jobs are bit-identical to one process's.

def test_a_split_path_traced_job_is_bit_identical_to_one_process(farm, start_server):
    api, _ = farm(workers=3)
    single = start_server("--threads", "1")
    body = {"scene": tiny_scene(width=48, height=48), "settings": {"spp": 64, "spp_per_pass": 4}}
    job, split = rendered(api, {**body, "task_passes": 3})
    assert job["passes_done"] == 16 and job["stats"]["tasks"] == 6, job
    _, whole = rendered(single, body)
    assert split == whole


@pytest.mark.parametrize("settings, task_passes, passes, tasks", [
    pytest.param({"integrator": "path", "spp": 24, "spp_per_pass": 2}, 1, 12, 12, id="path"),
    pytest.param({"integrator": "photon", "photons": 2000, "spp": 8, "spp_per_pass": 1}, 3, 8, 3,
                 id="photon"),
    pytest.param({"integrator": "ppm", "photons": 2000, "spp": 12, "spp_per_pass": 1}, 20, 12, 1,
                 id="ppm"),
])
def test_split_jobs_of_each_integrator_are_bit_identical(farm, single, settings, task_passes,
                                                         passes, tasks):
    api, _ = farm(workers=3)
    body = {"scene": SCENE, "settings": {**settings, "seed": 7}}
    job, split = rendered(api, {**body, "task_passes": task_passes})
    assert job["passes_done"] == passes and job["passes_total"] == passes, job
    assert job["stats"]["tasks"] == tasks and job["stats"]["stop_reason"] == "spp", job
    one, whole = rendered(single, body)
    assert one["passes_done"] == passes, one
    assert split[0] == whole[0], "image.exr differs"
    assert split[1] == whole[1], "image.png differs"


def test_a_split_job_with_a_target_error_stops_at_the_same_pass(farm, single):
    api, _ = farm(workers=3)
    # Under auto (the indirect map, whose bias layer the tasks hand in too): 0.01 stops midway.
    body = {"scene": SCENE, "settings": {"spp": 64, "spp_per_pass": 1, "target_error": 0.01}}
    one, whole = rendered(single, body)
    stop = one["passes_done"]
    assert one["stats"]["stop_reason"] == "target_error" and 2 < stop < 64, one
    job, split = rendered(api, {**body, "task_passes": 3})
    assert job["passes_done"] == stop and job["stats"]["passes"] == stop, job
    assert job["stats"]["stop_reason"] == "target_error", job
    # Tasks rendered past the stop are dropped, and those begun may be handed in.
    assert math.ceil(stop / 3) <= job["stats"]["tasks"] <= math.ceil(64 / 3), job
    assert split == whole


# 2. Priorities, workers, blocklist, re-queue, cancel, events.

def test_higher_priority_jobs_are_claimed_first(farm):
    api, _ = farm(workers=0)
    body = {"scene": SCENE, "settings": {"spp": 8, "spp_per_pass": 2}, "task_passes": 2}
    low = submit_ok(api, {**body, "priority": -5})
    high = submit_ok(api, {**body, "priority": 5})
    later = submit_ok(api, {**body, "priority": 5})
    api.start_worker()
    done = [api.wait(j["id"], ENDED) for j in (high, later, low)]
    assert [j["state"] for j in done] == ["succeeded"] * 3, done
    # One worker, one task at a time: a job's first task is claimed after the one before it had
    # its tasks claimed; each ends (its last consolidation) in that order.
    for first, second in zip(done, done[1:]):
        assert first["started_at"] <= second["started_at"], (first, second)
        assert first["finished_at"] <= second["finished_at"], (first, second)


def test_workers_are_listed_with_their_tasks_until_stopped(farm):
    api, workers = farm(workers=3)
    listed = wait_workers(api, 3)
    for w in listed:
        assert w["host"] and w["cores"] >= 1 and w["threads"] == 1, w
        assert abs(w["last_heartbeat"] - time.time()) < 30, w
        assert w["tasks_done"] == 0 and w["tasks_failed"] == 0, w
    assert sorted(len(worker_row(api, w)) for w in workers) == [1, 1, 1], listed

    job = submit_ok(api, long_body(passes=48, task_passes=4))

    def all_rendering():
        busy = [w for w in workers_of(api) if w["task"] and w["task"]["job"] == job["id"]]
        return busy if len(busy) == 3 else None

    busy = wait_for(all_rendering, "3 workers rendering")
    for w in busy:
        task = w["task"]
        assert task["last_pass"] - task["first_pass"] == 4 and task["first_pass"] % 4 == 0, w
    r = api.post(f"/api/jobs/{job['id']}/cancel")
    assert r.status_code == 202, r.text
    assert api.wait(job["id"], ENDED, deadline=30)["state"] == "cancelled"

    gone = workers[0]
    gone.stop()
    assert gone.proc.returncode == 0, gone.log()
    left = wait_workers(api, 2)
    assert not worker_row(api, gone), left
    assert all(not w["task"] for w in left), left


def test_a_worker_failing_every_task_is_blocked_and_the_job_succeeds_on_the_others(farm, single):
    api, _ = farm(workers=2)
    bad = api.start_worker("--fail-every-task")
    wait_workers(api, 3)
    # Tasks of about 0.1 s: the bad worker, idle, takes some while the others render.
    body = {"scene": SCENE, "settings": {"spp": 12 * 128, "spp_per_pass": 128}}
    job, split = rendered(api, {**body, "task_passes": 1})
    assert job["stats"]["tasks"] == 12, job
    [row] = worker_row(api, bad)
    assert 0 < row["tasks_failed"] <= 2 and row["tasks_done"] == 0, row
    _, whole = rendered(single, body)
    assert split == whole


def test_a_job_failing_on_every_worker_fails_naming_the_failures(farm):
    api, _ = farm(workers=0)
    api.start_worker("--fail-every-task")
    api.start_worker("--fail-every-task")
    wait_workers(api, 2)
    job = submit_ok(api, {"scene": SCENE, "settings": {"spp": 8}, "task_passes": 1})
    done = api.wait(job["id"], ENDED, deadline=30)
    assert done["state"] == "failed", done
    assert "failed on 2 workers" in done["error"], done
    assert "--fail-every-task" in done["error"], done


def test_a_cancelled_split_job_requeued_renders_only_the_remaining_tasks(farm, single):
    api, workers = farm(workers=1)
    body = {"scene": SCENE, "settings": {"spp": 16 * 128, "spp_per_pass": 128}}
    job = submit_ok(api, {**body, "task_passes": 2})
    wait_for(lambda: api.job(job["id"])["passes_done"] >= 4, "4 passes merged")
    r = api.post(f"/api/jobs/{job['id']}/cancel")
    assert r.status_code == 202, r.text
    cancelled = api.wait(job["id"], ENDED, deadline=30)
    assert cancelled["state"] == "cancelled", cancelled
    kept = cancelled["passes_done"]
    assert 4 <= kept < 16 and kept % 2 == 0, cancelled

    r = api.post(f"/api/jobs/{job['id']}/requeue")
    assert r.status_code == 202, r.text
    assert r.json()["state"] == "queued" and r.json()["passes_done"] == kept, r.json()
    done = api.wait(job["id"], ENDED)
    assert done["state"] == "succeeded", done
    assert done["passes_done"] == 16 and done["stats"]["tasks"] == 8, done
    # Each pass merged once (a point a consolidation batch), and no task handed in twice.
    passes = [int(p["pass"]) for p in done["convergence"]]
    assert passes == sorted(set(passes)) and passes[-1] == 16, done["convergence"]
    [row] = worker_row(api, workers[0])
    assert row["tasks_done"] == 8, row
    _, whole = rendered(single, body)
    assert images(api, job["id"]) == whole

    assert_problem(api.post(f"/api/jobs/{job['id']}/requeue"), 409, detail="succeeded")
    assert_problem(api.post(f"/api/jobs/{UNKNOWN_ID}/requeue"), 404)


def test_a_sqlite_server_has_no_workers_and_no_requeue(single):
    r = single.get("/api/workers")
    assert r.status_code == 200 and r.json() == {"store": "sqlite", "workers": []}, r.text
    job = submit_ok(single, {"scene": SCENE, "settings": {"spp": 1}})
    assert single.wait(job["id"], ENDED)["state"] == "succeeded"
    assert_problem(single.post(f"/api/jobs/{job['id']}/requeue"), 409, detail="PostgreSQL")


def test_queued_and_running_split_jobs_are_cancelled(farm):
    api, _ = farm(workers=0)
    queued = submit_ok(api, long_body())
    r = api.post(f"/api/jobs/{queued['id']}/cancel")
    assert r.status_code == 202, r.text
    assert api.wait(queued["id"], ENDED, deadline=10)["state"] == "cancelled"

    for _ in range(2):
        api.start_worker()
    running = submit_ok(api, long_body(task_passes=2))
    wait_for(lambda: api.job(running["id"])["passes_done"] >= 2, "a task merged")
    r = api.post(f"/api/jobs/{running['id']}/cancel")
    assert r.status_code == 202, r.text
    done = api.wait(running["id"], ENDED, deadline=30)
    assert done["state"] == "cancelled" and done["passes_done"] < 48, done
    # A worker's row drops its task right after it gives the task back, a moment after the job
    # ended: wait for it rather than read it once.
    wait_for(lambda: all(not w["task"] for w in wait_workers(api, 2)), "both workers idle", 10)


def test_events_follow_the_passes_rendered_by_workers_to_the_end(farm):
    api, _ = farm(workers=3)
    wait_workers(api, 3)
    job = submit_ok(api, long_body(passes=60, spp_per_pass=128, task_passes=4))
    with concurrent.futures.ThreadPoolExecutor(1) as pool:
        stream = pool.submit(sse_events, api, job["id"], 120)
        # The preview is the film merged so far, served while the job runs.
        wait_for(lambda: api.job(job["id"])["passes_done"] >= 2, "a task merged")
        r = api.get(f"/api/jobs/{job['id']}/preview.png")
        assert r.status_code == 200 and r.headers["Content-Type"] == "image/png", r.text
        assert png_info(r.content) == (48, 48)
        assert api.job(job["id"])["state"] == "running", "the job ended too soon to be seen"
        events = stream.result(timeout=150)
    assert [kind for kind, _ in events] == ["progress"] * (len(events) - 1) + ["end"], events
    seen = [data["passes_done"] for _, data in events]
    assert seen == sorted(seen) and len(set(seen)) > 2, seen
    end = events[-1][1]
    assert end["state"] == "succeeded" and end["passes_done"] == 60, end
    # One convergence point a consolidation batch, in the order they were merged.
    passes = [int(p["pass"]) for p in end["convergence"]]
    assert passes == sorted(set(passes)) and passes[-1] == 60 and len(passes) >= 2, passes
    assert re.match(r"^\d{4}-", end["finished_at"]), end
