"""Scale-out faults a SIGKILL cannot reach (issue 40, acceptance 3; server/store/task.h): workers
whose clocks are a minute off, a worker cut off from PostgreSQL by a silent network, the
consolidator killed in the middle of a batch, a 2048x2048 job split over two workers, and a cancel
that must stop running tasks within seconds. Each job's image is compared with one SQLite
process's where the test is about counting (nothing lost, nothing counted twice)."""

import os
import re
import socket
import threading
import time

import pytest

from conftest import submit_ok, tiny_scene
from test_scale_out import ENDED, images, rendered, wait_for, worker_row, workers_of

pytestmark = [pytest.mark.scaleout, pytest.mark.timeout(300)]

SCENE = tiny_scene(width=48, height=48)
# pg_try_advisory_xact_lock's first key for consolidations (store/postgres/consolidation.cpp).
CONSOLIDATION_LOCK = 0x636f6e73
# libfaketime (Debian's faketime package), preloaded by env so that the worker keeps its pid.
FAKETIME = "/usr/lib/x86_64-linux-gnu/faketime/libfaketimeMT.so.1"


def shifted(seconds):
    """A command prefix that runs a program with its wall clock `seconds` off (as machines'
    clocks differ; their monotonic clocks, which time waits, only count)."""
    return ("env", f"LD_PRELOAD={FAKETIME}", f"FAKETIME={seconds:+d}s", "DONT_FAKE_MONOTONIC=1")


@pytest.fixture
def single(start_server):
    s = start_server("--threads", "1")
    yield s
    s.stop()


def sql(postgres, api, query):
    return postgres.psql(query, database=api.store.rsplit("/", 1)[1])


def tasks_of(postgres, api, job_id):
    """(first_pass, attempt, stalled_leases) of each task of a job."""
    out = sql(postgres, api, "SELECT first_pass, attempt, stalled_leases FROM tasks WHERE "
                             f"job_id = '{job_id}' ORDER BY first_pass")
    return [tuple(int(v) for v in line.split("|")) for line in out.split()]


def log_times(worker):
    """The times (Unix seconds) of a worker's log lines, by its own clock."""
    stamps = re.findall(r"^(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\.\d+)", worker.log(), re.M)
    return [time.mktime(time.strptime(s.split(".")[0], "%Y-%m-%d %H:%M:%S")) for s in stamps]


@pytest.mark.skipif(not os.path.exists(FAKETIME), reason="needs libfaketime (apt faketime)")
def test_workers_with_clocks_a_minute_off_take_no_live_task_and_fail_no_job(farm, postgres,
                                                                            single):
    # Short leases: a worker that judged them by its own clock, a minute ahead, would find every
    # lease expired and take live tasks; one a minute behind would think every worker gone.
    args = ("--lease-seconds", "3")
    api, [honest] = farm(workers=1, worker_args=args)
    ahead = api.start_worker(*args, prefix=shifted(60))
    behind = api.start_worker(*args, prefix=shifted(-60))
    # Tasks of about a second: each worker gets some.
    body = {"scene": SCENE, "task_passes": 2,
            "settings": {"spp": 48 * 512, "spp_per_pass": 512, "seed": 7, "time_limit": 120}}
    job = submit_ok(api, body)
    done = api.wait(job["id"], ENDED, deadline=120)
    assert done["state"] == "succeeded", done
    assert done["stats"]["stop_reason"] == "spp", done["stats"]
    # Each task claimed once: no lease taken from a live holder, none stalled.
    tasks = tasks_of(postgres, api, job["id"])
    assert len(tasks) == 24 and all(t[1:] == (1, 0) for t in tasks), tasks
    for w in (honest, ahead, behind):
        assert worker_row(api, w)[0]["tasks_done"] > 0, (w.name, workers_of(api))
    _, whole = rendered(single, {k: v for k, v in body.items() if k != "task_passes"})
    assert images(api, job["id"]) == whole
    # The clocks really were off (the workers' log lines are stamped by their own clocks).
    for w, offset in ((ahead, 60), (behind, -60)):
        w.stop()
        assert abs(log_times(w)[-1] - time.time() - offset) < 15, (w.name, w.log())


class SilentProxy:
    """A TCP proxy to PostgreSQL that can go silent: cut() keeps every connection open and reads
    what both ends send, but forwards nothing (a network that drops packets, as far as either end
    can tell); new connections are accepted and silent too."""

    def __init__(self, port):
        self.target = ("127.0.0.1", port)
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.silent = threading.Event()
        self.closed = False
        threading.Thread(target=self.accept, daemon=True).start()

    def accept(self):
        while not self.closed:
            try:
                client, _ = self.listener.accept()
            except OSError:
                return
            try:
                server = socket.create_connection(self.target)
            except OSError:
                client.close()
                continue
            for a, b in ((client, server), (server, client)):
                threading.Thread(target=self.pipe, args=(a, b), daemon=True).start()

    def pipe(self, source, sink):
        try:
            while True:
                data = source.recv(65536)
                if not data:
                    break
                if not self.silent.is_set():
                    sink.sendall(data)
        except OSError:
            pass
        for s in (source, sink):
            try:
                s.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass

    def cut(self):
        self.silent.set()

    def close(self):
        self.closed = True
        self.listener.close()


def test_a_worker_cut_off_from_postgres_stops_within_a_lease_and_holds_no_lock(farm, postgres,
                                                                               single):
    lease = 3
    api, [steady] = farm(workers=1, worker_args=("--lease-seconds", str(lease)))
    # The cut worker reaches the database through the proxy; a transaction it leaves open ends
    # after 2 s on the server (its connection string's own idle_in_transaction_session_timeout).
    port = int(re.search(r":(\d+)/", api.store).group(1))
    proxy = SilentProxy(port)
    through = (api.store.replace(f":{port}/", f":{proxy.port}/")
               + "?options=-c%20idle_in_transaction_session_timeout%3D2s")
    cut = api.start_worker("--lease-seconds", str(lease), store=through)
    try:
        body = {"scene": SCENE, "task_passes": 2,
                "settings": {"spp": 40 * 128, "spp_per_pass": 128, "seed": 8}}
        job = submit_ok(api, body)
        wait_for(lambda: [w for w in worker_row(api, cut) if w["task"]], "the cut worker renders")
        proxy.cut()
        cut_at = time.monotonic()
        # It stops rendering once its lease must have run out, though no heartbeat is answered.
        wait_for(lambda: "the lease ran out" in cut.log(), "the cut worker stops", lease + 5)
        assert time.monotonic() - cut_at < lease + 3, cut.log()
        done = api.wait(job["id"], ENDED, deadline=120)
        assert done["state"] == "succeeded", done
        _, whole = rendered(single, {k: v for k, v in body.items() if k != "task_passes"})
        assert images(api, job["id"]) == whole
        # Its sessions hold no lock and no open transaction past the server's timeouts.
        time.sleep(3)
        mine = f"application_name = 'caustic-worker-{cut.proc.pid}'"
        assert sql(postgres, api, "SELECT count(*) FROM pg_locks l JOIN pg_stat_activity a "
                                  f"USING (pid) WHERE {mine} AND l.locktype <> 'virtualxid'"
                   ).strip() == "0"
        assert sql(postgres, api, f"SELECT count(*) FROM pg_stat_activity WHERE {mine} AND "
                                  "state LIKE 'idle in transaction%'").strip() == "0"
    finally:
        proxy.close()
        cut.kill()


def consolidating_pid(postgres, api):
    """The process id of the worker whose backend holds a consolidation lock, if any."""
    out = sql(postgres, api, "SELECT a.application_name FROM pg_locks l JOIN pg_stat_activity a "
                             "USING (pid) WHERE l.locktype = 'advisory' AND l.classid = "
                             f"{CONSOLIDATION_LOCK} AND l.granted").split()
    for name in out:
        m = re.fullmatch(r"caustic-worker-(\d+)", name)
        if m:
            return int(m.group(1))
    return None


def test_the_consolidator_killed_mid_batch_loses_and_double_counts_nothing(farm, postgres,
                                                                          single):
    # Every task its own result (--hand-in-seconds 0) on a larger image: many batches, each long
    # enough to be caught holding the job's consolidation lock.
    args = ("--hand-in-seconds", "0", "--lease-seconds", "3")
    api, workers = farm(workers=2, worker_args=args)
    body = {"scene": tiny_scene(width=320, height=320), "task_passes": 1,
            "settings": {"spp": 60 * 4, "spp_per_pass": 4, "seed": 9}}
    job = submit_ok(api, body)
    kills = 0
    end = time.monotonic() + 90
    while kills < 2 and time.monotonic() < end:
        pid = consolidating_pid(postgres, api)
        victim = next((w for w in workers if w.alive() and w.proc.pid == pid), None)
        if victim:
            victim.kill()
            kills += 1
            workers.append(api.start_worker(*args))
        time.sleep(0.01)
    assert kills == 2, "no consolidation batch was caught running"
    done = api.wait(job["id"], ENDED, deadline=120)
    assert done["state"] == "succeeded" and done["passes_done"] == 60, done
    _, whole = rendered(single, {k: v for k, v in body.items() if k != "task_passes"})
    assert images(api, job["id"]) == whole


def test_a_2048_job_split_over_two_workers_succeeds_with_no_stalled_lease(farm, postgres):
    api, workers = farm(workers=2)
    body = {"scene": tiny_scene(width=2048, height=2048), "task_passes": 2,
            "settings": {"spp": 8, "spp_per_pass": 1, "seed": 10}}
    job = submit_ok(api, body)
    done = api.wait(job["id"], ENDED, deadline=240)
    assert done["state"] == "succeeded" and done["passes_done"] == 8, done
    tasks = tasks_of(postgres, api, job["id"])
    assert all(t[1:] == (1, 0) for t in tasks), tasks
    assert all(worker_row(api, w)[0]["tasks_done"] > 0 for w in workers), workers_of(api)


def test_a_cancelled_jobs_running_tasks_stop_within_seconds(farm):
    api, workers = farm(workers=2)
    body = {"scene": SCENE, "task_passes": 4,
            "settings": {"spp": 250 * 256, "spp_per_pass": 256}}
    job = submit_ok(api, body)
    wait_for(lambda: all(worker_row(api, w)[0]["task"] for w in workers), "both render")
    cancelled_at = time.monotonic()
    r = api.post(f"/api/jobs/{job['id']}/cancel")
    assert r.status_code == 202, r.text
    done = api.wait(job["id"], ENDED, deadline=10)
    assert done["state"] == "cancelled", done
    wait_for(lambda: not any(worker_row(api, w)[0]["task"] for w in workers), "both idle", 10)
    assert time.monotonic() - cancelled_at < 3, "the running tasks took too long to stop"
