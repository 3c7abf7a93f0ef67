"""Several API processes on one PostgreSQL store (docs/scale-out.md): a job submitted to one is
seen, followed and served by another; `serve --store ... --workers N` renders tasks itself; the
connection string's password is never printed."""

import pytest

from conftest import assert_problem, run_to_end, submit_ok, tiny_scene
from farm import Worker

pytestmark = pytest.mark.scaleout

BODY = {"scene": tiny_scene(width=40, height=40), "settings": {"spp": 24, "spp_per_pass": 2},
        "task_passes": 2}


def test_a_job_submitted_to_one_api_process_is_followed_on_another(farm, start_server):
    api, _ = farm(workers=1)
    other = start_server("--store", api.store, "--workers", "0")
    job = submit_ok(api, BODY)
    assert other.job(job["id"])["state"] in ("queued", "running", "succeeded")
    end = run_to_end(other, job["id"])  # events woken by NOTIFY from the worker's commits
    assert end["state"] == "succeeded" and end["passes_done"] == 12, end
    image = api.get(f"/api/jobs/{job['id']}/image.exr")
    assert image.status_code == 200
    assert other.get(f"/api/jobs/{job['id']}/image.exr").content == image.content
    # Either process lists it and deletes it for both.
    assert job["id"] in [j["id"] for j in other.get("/api/jobs").json()["jobs"]]
    assert other.delete(f"/api/jobs/{job['id']}").status_code == 204
    assert api.get(f"/api/jobs/{job['id']}").status_code == 404


def test_a_target_errors_tasks_hold_at_most_256_mib_of_pass_images(farm, postgres):
    api, _ = farm(workers=0)
    body = {"scene": tiny_scene(width=2048, height=2048),
            "settings": {"spp": 64, "spp_per_pass": 1, "target_error": 0.01, "preset": "none"}}
    # With the indirect photon map auto takes for this scene, a pass brings its bias image too:
    # 96 MiB a pass, 2 a task at most.
    auto = {**body, "settings": {**body["settings"], "preset": "auto"}, "task_passes": 3}
    assert_problem(api.submit(auto), 422, pointer="/task_passes",
                   detail="at most 2 passes a task")
    # 2048² is 48 MiB a pass: 5 a task at most. Asked for more: refused, naming the field.
    assert_problem(api.submit({**body, "task_passes": 6}), 422, pointer="/task_passes",
                   detail="at most 5 passes a task")
    assert submit_ok(api, {**body, "task_passes": 5})["state"] == "queued"
    # The server's default (8) is cut to fit.
    job = submit_ok(api, body)
    widest = postgres.psql(f"SELECT max(last_pass - first_pass) FROM tasks WHERE job_id = "
                           f"'{job['id']}'", database=api.store.rsplit("/", 1)[1])
    assert int(widest) == 5, widest


def test_serve_with_workers_renders_the_tasks_itself(postgres, start_server):
    store = postgres.create_database()
    api = start_server("--store", store, "--workers", "2", "--threads", "1")
    single = start_server("--threads", "1")
    split = run_to_end(api, submit_ok(api, BODY)["id"])
    whole = run_to_end(single, submit_ok(single, BODY)["id"])
    assert split["state"] == whole["state"] == "succeeded"
    assert split["stats"]["tasks"] == 6, split["stats"]
    assert (api.get(f"/api/jobs/{split['id']}/image.exr").content
            == single.get(f"/api/jobs/{whole['id']}/image.exr").content)
    workers = api.get("/api/workers").json()
    assert workers["store"] == "postgresql" and len(workers["workers"]) == 2, workers


def test_the_store_password_is_never_printed(postgres, start_server, caustic_bin, tmp_path):
    store = postgres.create_database()
    password = store.split("://", 1)[1].split("@", 1)[0].split(":", 1)[1]
    api = start_server("--store", store, "--workers", "0")
    worker = Worker(caustic_bin, store, str(tmp_path)).start()
    worker.stop()
    with open(api.out_path) as f:
        out = f.read()
    assert "postgresql://caustic:***@127.0.0.1:" in out, out
    for text in (out, api.log(), open(worker.out_path).read(), worker.log()):
        assert password not in text


def test_command_line_mistakes_are_named(caustic_bin, tmp_path):
    import subprocess
    r = subprocess.run([caustic_bin, "serve", "--workers", "0", "--data", str(tmp_path)],
                       capture_output=True, text=True, timeout=30)
    assert r.returncode == 2 and "--workers" in r.stderr and "postgresql" in r.stderr, r.stderr
    r = subprocess.run([caustic_bin, "worker"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 2 and "--store" in r.stderr, r.stderr
    r = subprocess.run([caustic_bin, "worker", "--store", "mysql://x"], capture_output=True,
                       text=True, timeout=30)
    assert r.returncode == 2 and "postgresql://" in r.stderr, r.stderr
    # A store that cannot be reached: exit 1, saying so, without the password.
    for command in (["worker"], ["serve", "--workers", "0", "--port", "0"]):
        r = subprocess.run([caustic_bin, *command, "--store-wait", "1", "--store",
                            "postgresql://u:secret-pw@127.0.0.1:1/x"], capture_output=True,
                           text=True, timeout=60)
        assert r.returncode == 1, (command, r)
        assert "cannot connect to the PostgreSQL store in 1 s (--store-wait)" in r.stderr, r.stderr
        assert "waiting up to 1 s for the PostgreSQL store" in r.stderr, r.stderr
        assert "secret-pw" not in r.stdout + r.stderr
