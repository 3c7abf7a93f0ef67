"""Work whose length a job controls stops at once: a cancel, and SIGTERM, during a job of endless
photon paths end it within 5 seconds. The job (issue 12's fuzzing find): a point light inside a
closed mirror sphere with max_depth 1e6. Perfect mirrors never end a path by Russian roulette, so
every photon path bounces a million times; before, admission spent 11 minutes on its pilot
tracing, the photon pass ignored cancellation, and a stopped server ran on at full CPU."""

import os
import signal
import time

from conftest import submit_ok

MIRROR_TRAP = {
    "camera": {"position": [0, 0, 0], "look_at": [0, 0, 1], "fov": 60, "width": 32, "height": 32},
    "materials": {"mirror": {"type": "mirror", "reflectance": [1, 1, 1]}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "flip_normals": True,
                "material": "mirror"}],
    "lights": [{"type": "point", "position": [0, 0.5, 0], "intensity": [1, 1, 1]}],
}


def trap_job(server):
    start = time.monotonic()
    job = submit_ok(server, {"scene": MIRROR_TRAP,
                             "settings": {"integrator": "photon", "max_depth": 1000000}})
    assert time.monotonic() - start < 5, "admission did rendering work"
    server.wait(job["id"], {"running"}, deadline=30)
    time.sleep(1.0)  # well into the endless work
    return job["id"]


def test_cancel_stops_endless_photon_paths(start_server):
    server = start_server("--threads", "2")
    job_id = trap_job(server)
    start = time.monotonic()
    r = server.post(f"/api/jobs/{job_id}/cancel")
    assert r.status_code == 202, r.text
    job = server.wait(job_id, {"cancelled", "failed", "succeeded"}, deadline=5)
    assert time.monotonic() - start < 5
    assert job["state"] == "cancelled", job


def test_sigterm_stops_the_server_during_endless_photon_paths(start_server):
    server = start_server("--threads", "2")
    trap_job(server)
    start = time.monotonic()
    os.killpg(server.proc.pid, signal.SIGTERM)
    server.proc.wait(timeout=5)
    assert time.monotonic() - start < 5
    assert server.proc.returncode == 0, server.log()
