"""Retention (issue 13) against the real `caustic serve`: finished jobs and their files
(data/jobs/<id>) go --keep-days after they finished and beyond the --max-stored-jobs most recently
finished; queued and running jobs stay however old; /metrics shows the data folder's disk use and
free space and what retention removed."""

import os
import re
import time

from conftest import run_to_end, submit_ok, tiny_job, tiny_scene

# 0.00004 days is 3.456 s: long enough to see a finished job's files before they go.
KEEP_DAYS = 0.00004
KEEP_SECONDS = KEEP_DAYS * 86400


def metrics(server):
    """/metrics as {sample name with labels: value}, checking every line's syntax."""
    r = server.get("/metrics")
    assert r.status_code == 200, r.text
    values = {}
    for line in r.text.splitlines():
        if line and not line.startswith("#"):
            m = re.fullmatch(r'([a-z_]+(?:\{[a-z_]+="[a-z_]+"\})?) (\S+)', line)
            assert m, f"not a Prometheus sample: {line!r}"
            values[m.group(1)] = float(m.group(2))
    return values, r.text


def job_dir(server, job_id):
    return os.path.join(server.data, "jobs", job_id)


def wait_until(condition, what, deadline=30):
    end = time.monotonic() + deadline
    while not condition():
        assert time.monotonic() < end, f"{what} did not happen within {deadline} s"
        time.sleep(0.05)


def whole_log(server):
    """The server's stderr, all of it (Server.log() keeps the tail, mostly access-log lines)."""
    with open(server.log_path, encoding="utf-8", errors="replace") as f:
        return f.read()


def gone(server, job_id):
    return (server.get(f"/api/jobs/{job_id}").status_code == 404
            and not os.path.exists(job_dir(server, job_id)))


def long_job(server):
    """A job that renders for far longer than a test (teardown's server stop ends it)."""
    job = submit_ok(server, {"scene": "cornell-box",
                             "settings": {"spp": 4096, "spp_per_pass": 1, "time_limit": 120}})
    return job["id"]


def test_finished_jobs_and_their_files_go_after_keep_days(start_server):
    server = start_server("--threads", "2", "--keep-days", str(KEEP_DAYS),
                          "--sweep-seconds", "0.2")
    finished = [tiny_job(server, seed=seed)["id"] for seed in (1, 2)]
    for job_id in finished:
        assert run_to_end(server, job_id)["state"] == "succeeded"
    # Just finished: the job and its images are still there.
    assert server.get(f"/api/jobs/{finished[0]}/image.png").status_code == 200
    assert os.path.isfile(os.path.join(job_dir(server, finished[0]), "image.exr"))
    # A running job and a queued one behind it (one worker), older than --keep-days by the end.
    running = long_job(server)
    server.wait(running, {"running"})
    queued = tiny_job(server, seed=3)["id"]
    for job_id in finished:
        wait_until(lambda: gone(server, job_id), f"removing finished job {job_id}")
    submitted = time.monotonic()
    sweeps = metrics(server)[0]["caustic_retention_sweeps_total"]
    wait_until(lambda: time.monotonic() - submitted > KEEP_SECONDS
               and metrics(server)[0]["caustic_retention_sweeps_total"] > sweeps + 2,
               "sweeps past the queued and running jobs' --keep-days")
    assert server.job(running)["state"] == "running"
    assert server.job(queued)["state"] == "queued"
    assert os.path.isfile(os.path.join(job_dir(server, running), "checkpoint.bin"))
    values, text = metrics(server)
    assert values['caustic_retention_jobs_removed_total{reason="keep_days"}'] == 2
    assert values['caustic_retention_jobs_removed_total{reason="max_stored_jobs"}'] == 0
    assert "# TYPE caustic_retention_jobs_removed_total counter" in text
    # A cancelled job is a finished one: it goes too, and the queued one then renders.
    assert server.post(f"/api/jobs/{running}/cancel").status_code == 202
    server.wait(running, {"cancelled"})
    wait_until(lambda: gone(server, running), "removing the cancelled job")
    # The sweep logs a removal after the job has left the store: wait for the line.
    for job_id in finished + [running]:
        pattern = r"retention removed \d+ finished job\(s\).*" + job_id
        wait_until(lambda: re.search(pattern, whole_log(server)), f"the log line removing {job_id}")
    server.healthy()


def test_max_stored_jobs_keeps_the_most_recently_finished(start_server):
    server = start_server("--threads", "2", "--max-stored-jobs", "2", "--keep-days", "0",
                          "--sweep-seconds", "0.2")
    ids = []
    for seed in range(5):
        ids.append(tiny_job(server, seed=10 + seed)["id"])
        assert run_to_end(server, ids[-1])["state"] == "succeeded"
    for job_id in ids[:3]:
        wait_until(lambda: gone(server, job_id), f"removing job {job_id}")
    listed = [j["id"] for j in server.get("/api/jobs", params={"limit": 100}).json()["jobs"]]
    assert listed == [ids[4], ids[3]]
    for job_id in ids[3:]:
        assert os.path.isfile(os.path.join(job_dir(server, job_id), "image.png"))
    values, _ = metrics(server)
    assert values['caustic_retention_jobs_removed_total{reason="max_stored_jobs"}'] == 3
    assert values['caustic_retention_jobs_removed_total{reason="keep_days"}'] == 0
    # --keep-days 0: the two kept stay, whatever their age.
    time.sleep(1)
    assert [j["id"] for j in server.get("/api/jobs").json()["jobs"]] == [ids[4], ids[3]]


def test_metrics_show_the_data_folders_disk_use_and_free_space(start_server):
    server = start_server("--threads", "2", "--sweep-seconds", "0.2")
    job = tiny_job(server, seed=20)
    assert run_to_end(server, job["id"])["state"] == "succeeded"
    sweeps = metrics(server)[0]["caustic_retention_sweeps_total"]
    wait_until(lambda: metrics(server)[0]["caustic_retention_sweeps_total"] > sweeps,
               "a sweep after the job finished")
    values, text = metrics(server)
    for name, kind in (("caustic_data_bytes", "gauge"),
                       ("caustic_data_filesystem_avail_bytes", "gauge"),
                       ("caustic_data_filesystem_size_bytes", "gauge"),
                       ("caustic_retention_sweeps_total", "counter")):
        assert f"# TYPE {name} {kind}" in text and f"# HELP {name} " in text
    # What du counts: the store and the job's images at least.
    used = 0
    for folder, _, files in os.walk(server.data):
        used += sum(os.lstat(os.path.join(folder, f)).st_blocks * 512 for f in files)
    assert used > 0
    assert values["caustic_data_bytes"] >= os.lstat(
        os.path.join(job_dir(server, job["id"]), "image.exr")).st_blocks * 512
    assert 0.5 * used <= values["caustic_data_bytes"] <= 2 * used + (1 << 20)
    fs = os.statvfs(server.data)
    assert values["caustic_data_filesystem_size_bytes"] == fs.f_blocks * fs.f_frsize
    assert 0 < values["caustic_data_filesystem_avail_bytes"] <= fs.f_blocks * fs.f_frsize
    assert abs(values["caustic_data_filesystem_avail_bytes"] - fs.f_bavail * fs.f_frsize) \
        < 256 << 20  # other processes write to the same file system meanwhile


def test_unused_assets_go_after_keep_days_and_a_job_holds_its_own(start_server):
    server = start_server("--threads", "2", "--keep-days", str(KEEP_DAYS), "--sweep-seconds",
                          "0.2")
    triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"

    def upload(text):
        r = server.post("/api/assets", data=text.encode(), headers={"Content-Type": "model/obj"})
        assert r.status_code == 201, r.text
        return r.json()["id"]

    unused = upload(triangle)
    held = upload(triangle + "v 0 0 1\nf 1 2 4\n")
    # A long job holds `held` (a queued or running job's asset is never removed).
    scene = tiny_scene(width=256, height=256)
    scene["shapes"] = scene["shapes"] + [
        {"type": "mesh", "asset": held, "material": "white", "transform": {"scale": 0.1}}]
    job = submit_ok(server, {"scene": scene,
                             "settings": {"spp": 65536, "spp_per_pass": 1, "time_limit": 120}})
    wait_until(lambda: server.get(f"/api/assets/{unused}").status_code == 404,
               "removing the unused asset")
    wait_until(lambda: re.search(r"retention removed 1 asset\(s\).*" + unused, whole_log(server)),
               "the log line removing the unused asset")
    time.sleep(2 * KEEP_SECONDS)
    assert server.get(f"/api/assets/{held}").status_code == 200
    assert metrics(server)[0]["caustic_retention_assets_removed_total"] == 1
    # Once its job is gone (deleted here; retention would in time), the asset goes too.
    assert server.delete(f"/api/jobs/{job['id']}").status_code == 204
    wait_until(lambda: server.get(f"/api/assets/{held}").status_code == 404,
               "removing the asset after its job was deleted")
    assert metrics(server)[0]["caustic_retention_assets_removed_total"] == 2
