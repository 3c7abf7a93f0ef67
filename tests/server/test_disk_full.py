"""A full disk (issue 13) against the real `caustic serve`, on a small tmpfs each test mounts (root
only: CI runs them as root; elsewhere they skip, saying why). The data folder lives on it, and a
filler file takes the rest. Submissions and uploads get 507 with a clear detail; a running job
fails with a clear reason; nothing in the store is corrupted (PRAGMA integrity_check, and a new
server on the folder lists the jobs); the same server serves again once the filler is deleted.
The server's log stays outside the tmpfs."""

import errno
import os
import sqlite3
import subprocess
import tempfile
import time

import pytest

from conftest import TINY_SCENE, Server, assert_problem, run_to_end, submit_ok, tiny_scene

MOUNT_SIZE = "24m"


class Tmpfs:
    """A mounted tmpfs: a data folder on it, a filler file, and the servers started on it."""

    def __init__(self, binary, mount, logs):
        self.binary, self.mount, self.logs = binary, mount, logs
        self.data = os.path.join(mount, "data")
        self.filler = os.path.join(mount, "filler")
        self.servers = []

    def start(self, *args):
        """A server with --data on the tmpfs and its log in a normal temporary folder."""
        server = Server(self.binary, self.logs, ("--threads", "2", *args))
        server.data = self.data
        server.args[server.args.index("--data") + 1] = self.data
        self.servers.append(server)
        return server.start()

    def free(self):
        s = os.statvfs(self.mount)
        return s.f_bavail * s.f_frsize

    def fill(self, leave=0):
        """Grows the filler until at most `leave` bytes are free (or a write finds no room)."""
        fd = os.open(self.filler, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
        try:
            while (free := self.free()) > leave:
                try:
                    os.write(fd, b"\xa5" * min(1 << 20, free - leave))
                except OSError as e:
                    if e.errno != errno.ENOSPC:
                        raise
                    return
        finally:
            os.close(fd)

    def unfill(self):
        os.remove(self.filler)


@pytest.fixture
def tmpfs(caustic_bin):
    if os.geteuid() != 0:
        reason = "mounting a tmpfs needs root (CI runs the disk-full tests as root)"
        print(f"test_disk_full: skipped: {reason}")
        pytest.skip(reason)
    mount = tempfile.mkdtemp(prefix="caustic-tmpfs-")
    logs = tempfile.mkdtemp(prefix="caustic-tmpfs-logs-")
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={MOUNT_SIZE},mode=0700",
                        "caustic-test", mount], capture_output=True, text=True, timeout=30)
    if r.returncode != 0:
        os.rmdir(mount)
        reason = f"cannot mount a tmpfs at {mount}: {(r.stderr or r.stdout).strip()}"
        print(f"test_disk_full: skipped: {reason}")
        pytest.skip(reason)
    fs = Tmpfs(caustic_bin, mount, logs)
    try:
        yield fs
    finally:
        for server in fs.servers:
            server.stop()
        # Unmount whatever happened; lazily if something still holds it.
        if subprocess.run(["umount", mount], capture_output=True, timeout=30).returncode != 0:
            subprocess.run(["umount", "-l", mount], capture_output=True, timeout=30)
        os.rmdir(mount)
        subprocess.run(["rm", "-rf", logs], timeout=30)


def integrity(data):
    db = sqlite3.connect(f"file:{os.path.join(data, 'jobs.sqlite3')}?mode=ro", uri=True)
    try:
        return db.execute("PRAGMA integrity_check").fetchall()
    finally:
        db.close()


def listed(server):
    r = server.get("/api/jobs", params={"limit": 100})
    assert r.status_code == 200, r.text
    return {j["id"]: j["state"] for j in r.json()["jobs"]}


def checkpoint_size(server, job_id):
    try:
        return os.path.getsize(os.path.join(server.data, "jobs", job_id, "checkpoint.bin"))
    except OSError:
        return 0


def tiny_job_ok(server, seed):
    job = submit_ok(server, {"scene": TINY_SCENE, "settings": {"spp": 4, "seed": seed}})
    assert run_to_end(server, job["id"])["state"] == "succeeded"
    return job["id"]


def reopens_with(tmpfs, server, jobs):
    """Stops `server`; the store is intact and a new server on the folder lists `jobs`."""
    server.stop()
    assert integrity(tmpfs.data) == [("ok",)]
    again = tmpfs.start()
    assert listed(again) == jobs
    again.healthy()


def test_full_disk_refuses_jobs_fails_the_running_one_and_recovers(tmpfs):
    server = tmpfs.start("--min-free-mib", "1", "--lease-seconds", "2")
    before = tiny_job_ok(server, seed=1)
    # A job of many short passes, each checkpointed (a 160x160 film: films are stored compactly,
    # and half a checkpoint must leave room for the job's failure in the store).
    running = submit_ok(server, {"scene": tiny_scene(width=160, height=160),
                                 "settings": {"spp": 60000, "spp_per_pass": 1,
                                              "time_limit": 100}})["id"]
    end = time.monotonic() + 30
    while (size := checkpoint_size(server, running)) == 0:
        assert time.monotonic() < end, "no checkpoint in time"
        time.sleep(0.05)
    assert size > 64 << 10, size
    # Leave less free space than a checkpoint takes, but some: the failure must fit in the store.
    # The job frees its old checkpoint on each rename, so fill again until its next write fails.
    end = time.monotonic() + 30
    while (job := server.job(running))["state"] == "running":
        assert time.monotonic() < end, f"the job still runs on a full disk: {job}"
        tmpfs.fill(leave=size // 2)
        time.sleep(0.05)
    assert job["state"] == "failed", job
    assert "the data folder's disk is full while writing" in job["error"], job
    assert "free space and submit the job again" in job["error"], job
    assert not os.path.exists(os.path.join(server.data, "jobs", running))
    # No leftover temporary files.
    for folder, _, files in os.walk(tmpfs.data):
        assert not [f for f in files if ".tmp" in f], (folder, files)

    # Submissions get 507 before anything is written; reading still works.
    tmpfs.fill(leave=0)
    body = assert_problem(server.submit({"scene": TINY_SCENE, "settings": {"spp": 4}}), 507,
                          detail="the data folder's disk is full")
    assert "--min-free-mib" in body["detail"], body
    assert listed(server) == {before: "succeeded", running: "failed"}
    assert server.get(f"/api/jobs/{before}/image.png").status_code == 200
    metrics = server.get("/metrics").text
    assert "caustic_data_filesystem_avail_bytes " in metrics
    server.healthy()

    # Space freed: the same server serves a new job to success.
    tmpfs.unfill()
    after = tiny_job_ok(server, seed=2)
    assert server.get(f"/api/jobs/{after}/image.exr").status_code == 200
    reopens_with(tmpfs, server, {before: "succeeded", running: "failed", after: "succeeded"})


def test_store_writes_on_a_full_disk_get_507(tmpfs):
    # No free-space margin: the submission reaches the store, whose write fails (SQLITE_FULL, or
    # an I/O error with ENOSPC) and is rolled back.
    server = tmpfs.start("--min-free-mib", "0")
    before = tiny_job_ok(server, seed=3)
    tmpfs.fill(leave=0)
    for attempt in range(3):
        assert_problem(server.submit({"scene": TINY_SCENE, "settings": {"spp": 4}}), 507,
                       detail="the data folder's disk is full: the job store cannot write")
    assert listed(server) == {before: "succeeded"}
    server.healthy()
    tmpfs.unfill()
    after = tiny_job_ok(server, seed=4)
    reopens_with(tmpfs, server, {before: "succeeded", after: "succeeded"})


# A small valid OBJ: one triangle.
TRIANGLE_OBJ = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"


@pytest.mark.parametrize("min_free_mib", ["1", "0"])
def test_uploads_on_a_full_disk_get_507(tmpfs, min_free_mib):
    # --min-free-mib 1 refuses the upload before it writes; with 0 the store's own write fails.
    server = tmpfs.start("--min-free-mib", min_free_mib)
    tmpfs.fill(leave=0)
    r = server.post("/api/assets", data=TRIANGLE_OBJ,
                    headers={"Content-Type": "model/obj"})
    assert_problem(r, 507, detail="disk is full")
    assert ("--min-free-mib" if min_free_mib != "0" else "job store cannot write") \
        in r.json()["detail"], r.text
    server.healthy()
    tmpfs.unfill()
    r = server.post("/api/assets", data=TRIANGLE_OBJ,
                    headers={"Content-Type": "model/obj"})
    assert r.status_code == 201, r.text
    server.stop()
    assert integrity(tmpfs.data) == [("ok",)]
