"""Integration tests of the HTTP API against the real `caustic serve`, continued: cancelling a
queued and a running job, deleting (a finished job; a running one, whose event stream then ends
with `deleted`), the preview during a render, event streams of several clients, Idempotency-Key,
and the 404s (unknown jobs and routes)."""

import json
import threading
import time

import pytest

from conftest import (TINY_SCENE, UNKNOWN_ID, assert_problem, png_info, run_to_end, sse_events,
                      tiny_job)


# Cancel, delete, preview.

def test_cancel_queued_and_running(server, long_job):
    queued = tiny_job(server, seed=400)
    assert server.job(queued["id"])["state"] == "queued"  # the one worker renders long_job
    r = server.post(f"/api/jobs/{queued['id']}/cancel")
    assert r.status_code == 202, r.text
    job = r.json()
    assert job["state"] == "cancelled"  # a queued job at once
    assert "cancel" not in job["links"] and job["finished_at"]
    assert_problem(server.get(f"/api/jobs/{queued['id']}/image.png"), 409)

    r = server.post(f"/api/jobs/{long_job}/cancel")
    assert r.status_code == 202, r.text
    assert r.json()["cancel_requested"] is True
    end = run_to_end(server, long_job, deadline=60)
    assert end["state"] == "cancelled", end
    assert end["passes_done"] < 4096
    assert_problem(server.get(f"/api/jobs/{long_job}/image.exr"), 409)
    # Cancelling a finished job changes nothing.
    r = server.post(f"/api/jobs/{long_job}/cancel")
    assert r.status_code == 202 and r.json()["state"] == "cancelled"


def test_preview_during_render(server, long_job):
    end = time.monotonic() + 60
    while True:
        r = server.get(f"/api/jobs/{long_job}/preview.png")
        if r.status_code == 200:
            break
        assert_problem(r, 404, detail="preview.png")
        assert time.monotonic() < end, "no preview in time"
        time.sleep(0.1)
    assert r.headers["Content-Type"] == "image/png"
    assert r.headers["Cache-Control"] == "no-store"
    assert png_info(r.content) == (512, 512)
    job = server.job(long_job)
    assert job["state"] == "running" and job["passes_done"] >= 1
    assert 0 < job["progress"] < 1
    # The result does not exist until the job has succeeded.
    assert_problem(server.get(f"/api/jobs/{long_job}/image.png"), 409, detail="running")
    assert_problem(server.get(f"/api/jobs/{long_job}/image.exr"), 409)


def test_delete_finished_job(server):
    job = tiny_job(server, seed=500)
    run_to_end(server, job["id"])
    r = server.delete(f"/api/jobs/{job['id']}")
    assert r.status_code == 204 and r.content == b""
    for path in ("", "/events", "/image.png", "/image.exr", "/preview.png"):
        assert_problem(server.get(f"/api/jobs/{job['id']}{path}"), 404)
    assert_problem(server.delete(f"/api/jobs/{job['id']}"), 404)
    assert_problem(server.post(f"/api/jobs/{job['id']}/cancel"), 404)
    listed = server.get("/api/jobs", params={"limit": 100}).json()["jobs"]
    assert job["id"] not in [j["id"] for j in listed]


def test_delete_running_job_ends_its_event_stream(server, long_job):
    r = server.get(f"/api/jobs/{long_job}/events", stream=True, timeout=(10, 60))
    assert r.status_code == 200
    lines = r.iter_lines(decode_unicode=True)
    assert next(lines) == "event: progress"
    deleted = server.delete(f"/api/jobs/{long_job}")
    assert deleted.status_code == 204
    rest = list(lines)
    r.close()
    assert "event: deleted" in rest, rest[-5:]
    assert f'data: {{"id":"{long_job}"}}' in rest
    assert_problem(server.get(f"/api/jobs/{long_job}"), 404)


def test_event_streams_of_many_clients(server):
    job = tiny_job(server, seed=600, spp=8)
    results = []

    def watch():
        results.append(sse_events(server, job["id"])[-1])

    threads = [threading.Thread(target=watch) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(60)
    assert len(results) == 4
    assert all(kind == "end" and data["state"] == "succeeded" for kind, data in results)


# Idempotency-Key.

def test_idempotency_key(server):
    body = json.dumps({"scene": TINY_SCENE, "settings": {"spp": 1, "seed": 700}})
    headers = {"Idempotency-Key": "test-idempotency-1", "Content-Type": "application/json"}
    first = server.post("/api/jobs", data=body, headers=headers)
    assert first.status_code == 202, first.text
    again = server.post("/api/jobs", data=body, headers=headers)
    assert again.status_code == 202
    assert again.text == first.text
    assert again.headers["Location"] == first.headers["Location"]
    job_id = first.json()["id"]
    listed = server.get("/api/jobs", params={"limit": 100}).json()["jobs"]
    assert [j["id"] for j in listed].count(job_id) == 1
    # The same key with another body is refused; the job stays as it was.
    other = json.dumps({"scene": TINY_SCENE, "settings": {"spp": 2, "seed": 700}})
    assert_problem(server.post("/api/jobs", data=other, headers=headers), 409,
                   detail="test-idempotency-1")
    assert server.job(job_id)["settings"]["spp"] == 1
    # The key still answers after the job has finished.
    run_to_end(server, job_id)
    assert server.post("/api/jobs", data=body, headers=headers).headers["Location"] == \
        first.headers["Location"]
    # Another key, or none, is another job.
    third = server.post("/api/jobs", data=body,
                        headers={**headers, "Idempotency-Key": "test-idempotency-2"})
    assert third.status_code == 202 and third.json()["id"] != job_id
    fourth = server.post("/api/jobs", data=body, headers={"Content-Type": "application/json"})
    assert fourth.status_code == 202 and fourth.json()["id"] not in (job_id, third.json()["id"])


def test_idempotency_key_of_a_refused_request(server):
    headers = {"Idempotency-Key": "test-idempotency-refused"}
    assert_problem(server.submit({"scene": 1}, headers=headers), 422, "/scene")
    # A refused request made no job and stored nothing: the key is still free.
    r = server.submit({"scene": TINY_SCENE, "settings": {"spp": 1}}, headers=headers)
    assert r.status_code == 202, r.text


# Not found.

@pytest.mark.parametrize("method,path", [
    ("GET", f"/api/jobs/{UNKNOWN_ID}"),
    ("GET", f"/api/jobs/{UNKNOWN_ID}/events"),
    ("GET", f"/api/jobs/{UNKNOWN_ID}/image.png"),
    ("GET", f"/api/jobs/{UNKNOWN_ID}/image.exr"),
    ("GET", f"/api/jobs/{UNKNOWN_ID}/preview.png"),
    ("POST", f"/api/jobs/{UNKNOWN_ID}/cancel"),
    ("DELETE", f"/api/jobs/{UNKNOWN_ID}"),
])
def test_unknown_job_is_404(server, method, path):
    assert_problem(server.request(method, path), 404, detail=UNKNOWN_ID)


@pytest.mark.parametrize("path", [
    "/api/nothing", "/api/jobs/", "/api/jobs/not-an-id", f"/api/jobs/{UNKNOWN_ID}/image.jpg",
    f"/api/jobs/{UNKNOWN_ID}/checkpoint.bin", "/no-such-file.html",
])
def test_unknown_route_is_404(server, path):
    assert_problem(server.get(path), 404)


def test_preview_of_a_job_without_a_pass_is_404(server, long_job):
    queued = tiny_job(server, seed=800)["id"]
    assert server.job(queued)["state"] == "queued"
    assert_problem(server.get(f"/api/jobs/{queued}/preview.png"), 404, detail="preview.png")
    assert_problem(server.get(f"/api/jobs/{queued}/image.png"), 409, detail="queued")
    assert server.post(f"/api/jobs/{queued}/cancel").status_code == 202


def test_static_page(server):
    r = server.get("/")
    assert r.status_code == 200 and r.headers["Content-Type"].startswith("text/html")
    assert server.get("/index.html").content == r.content
