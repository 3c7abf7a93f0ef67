"""Scale-out under faults (issue 14, acceptance 3; server/store/task.h "Faults"): while split jobs
render, workers are killed with SIGKILL mid-task 10 times, the API process once, and PostgreSQL is
restarted once; every job still succeeds exactly once, no pass is counted twice, and every image is
bit-identical to the same job rendered by one SQLite process.

The faults' order, gaps and victims come from a seeded random.Random: the seed is printed (run
with -s), and CAUSTIC_FAULT_SEED=N replays a schedule."""

import os
import random
import signal
import time

import pytest
import requests

from conftest import submit_ok, tiny_scene
from farm import Worker

pytestmark = [pytest.mark.scaleout, pytest.mark.timeout(360)]

# Workers get killed tasks back quickly (2 s leases) and never give up on a task that stalls.
WORKER_ARGS = ("--lease-seconds", "2", "--max-stalled-leases", "1000")
WORKER_KILLS = 10
ENDED = ("succeeded", "failed", "cancelled")


def fault_jobs():
    """The jobs, as (name, body): small scenes, tasks of a fraction of a second to about a second
    on one thread."""
    scene = tiny_scene(width=64, height=64)
    return [
        ("path", {"scene": scene, "task_passes": 8,
                  "settings": {"spp": 64 * 128, "spp_per_pass": 64, "seed": 1}}),
        ("photon", {"scene": scene, "task_passes": 4,
                    "settings": {"integrator": "photon", "spp": 4 * 64, "spp_per_pass": 4,
                                 "photons": 100000, "seed": 2}}),
        ("ppm", {"scene": scene, "task_passes": 8,
                 "settings": {"integrator": "ppm", "spp": 4 * 96, "spp_per_pass": 4,
                              "photons": 100000, "seed": 3}}),
        # Reaches its target near pass 50 of 128: later tasks are dropped, some while running.
        ("target_error", {"scene": scene, "task_passes": 8,
                          "settings": {"spp": 64 * 128, "spp_per_pass": 64,
                                       "target_error": 0.0035, "seed": 4}}),
        ("path-priority", {"scene": tiny_scene(width=80, height=80), "task_passes": 6,
                           "priority": 10,
                           "settings": {"spp": 48 * 72, "spp_per_pass": 48, "seed": 5}}),
    ]


def schedule(rng):
    """The faults in order, each with the seconds to wait before it."""
    kinds = ["worker"] * WORKER_KILLS + ["api", "postgres"]
    rng.shuffle(kinds)
    return [(kind, round(rng.uniform(0.2, 1.0), 2)) for kind in kinds]


class Farm:
    """The processes of the test (the API is replaced when killed) and what it saw of the jobs."""

    def __init__(self, api, workers, postgres, start_server, new_worker):
        self.api = api
        self.store = api.store
        self.workers = list(workers)
        self.postgres = postgres
        self.start_server = start_server
        self.new_worker = new_worker
        self.replacements = []
        self.ids = {}        # job name -> id
        self.seen = {}       # job id -> [states seen, in order, without repeats]
        self.finished = {}   # job id -> finished_at when first seen succeeded
        self.database = self.store.rsplit("/", 1)[1].split("?")[0]

    def sql(self, query):
        return self.postgres.psql(query, database=self.database)

    def held_task(self, worker):
        """The task whose lease `worker`'s process holds in PostgreSQL, if any."""
        return self.sql(f"SELECT job_id || ' ' || first_pass || '-' || last_pass FROM tasks WHERE "
                        f"state = 'running' AND lease_owner ~ '-{worker.proc.pid}-[0-9]+-[0-9]+$' "
                        f"LIMIT 1").strip()

    def ask(self, path, deadline=60):
        """GET `path` from the API, waiting out a restart of it or of PostgreSQL."""
        end = time.monotonic() + deadline
        while True:
            try:
                r = self.api.get(path, timeout=10)
                if r.status_code == 200:
                    return r.json()
                problem = f"{r.status_code} {r.text[:300]}"
            except requests.RequestException as e:
                problem = repr(e)
            assert time.monotonic() < end, f"GET {path} kept failing: {problem}"
            time.sleep(0.1)

    def ask_bytes(self, path):
        r = self.api.get(path)
        assert r.status_code == 200, r.text
        return r.content

    def watch(self):
        """Polls every job; checks that a succeeded one stays so with the same finished_at.
        Returns the jobs not ended yet."""
        running = []
        for name, job_id in self.ids.items():
            job = self.ask(f"/api/jobs/{job_id}")
            states = self.seen.setdefault(job_id, [])
            if not states or states[-1] != job["state"]:
                states.append(job["state"])
            if job_id in self.finished:
                assert job["state"] == "succeeded" and job["finished_at"] == \
                    self.finished[job_id], (name, states, job)
            elif job["state"] == "succeeded":
                self.finished[job_id] = job["finished_at"]
            if job["state"] not in ENDED:
                running.append(name)
        return running

    def rendering(self, deadline=60):
        """The live worker processes that render a task now (GET /api/workers), waiting for one."""
        end = time.monotonic() + deadline
        while True:
            pids = set()
            for w in self.ask("/api/workers")["workers"]:
                if w["task"] is not None:
                    pids.add(int(w["id"].rsplit("-", 3)[1]))  # host-pid-random-thread
            busy = [w for w in self.workers if w.alive() and w.proc.pid in pids]
            if busy:
                return busy
            assert self.watch(), "every job ended before the faults were all made"
            assert time.monotonic() < end, "no worker rendered a task for a minute"
            time.sleep(0.05)

    def kill_worker(self, rng):
        # GET /api/workers may show a task just handed in: the store says which lease it holds.
        while True:
            victim = rng.choice(sorted(self.rendering(), key=lambda w: w.proc.pid))
            task = self.held_task(victim)
            if task:
                break
            time.sleep(0.05)
        victim.kill(signal.SIGKILL)
        self.workers.remove(victim)
        replacement = self.new_worker()
        self.replacements.append(replacement)
        self.workers.append(replacement.start())
        return (f"worker pid {victim.proc.pid} killed rendering task {task}, pid "
                f"{replacement.proc.pid} started")

    def kill_api(self):
        old = self.api
        os.killpg(old.proc.pid, signal.SIGKILL)
        old.proc.wait(timeout=30)
        self.api = self.start_server("--store", self.store, "--workers", "0")
        self.api.store = self.store
        return f"API pid {old.proc.pid} killed, pid {self.api.proc.pid} started"

    def restart_postgres(self, rng):
        self.rendering()  # a job runs
        mode = rng.choice(["immediate", "fast"])
        began = time.monotonic()
        self.postgres.restart(mode)
        took = time.monotonic() - began
        # Every worker process that lived through it talks to the store again.
        since = float(self.sql("SELECT extract(epoch FROM now())"))
        alive = {w.proc.pid for w in self.workers if w.alive()}
        end = time.monotonic() + 20
        while True:
            seen = {int(row.rsplit("-", 3)[1]) for row in self.sql(
                f"SELECT id FROM workers WHERE last_seen > {since}").split()}
            if alive <= seen:
                break
            assert time.monotonic() < end, f"workers {alive - seen} lost the store for good"
            time.sleep(0.1)
        return (f"PostgreSQL restarted ({mode}) in {took:.1f} s; the {len(alive)} workers were "
                f"back after {time.monotonic() - began - took:.1f} s more")

    def stop_replacements(self):
        for w in self.replacements:
            w.stop()


def wait_all(farm, deadline=180):
    end = time.monotonic() + deadline
    while farm.watch():
        assert time.monotonic() < end, f"jobs not ended: {farm.seen}"
        time.sleep(0.1)


def check_database(farm, jobs):
    """Each job's tasks in PostgreSQL: done once each, their passes adding up to the job's."""
    done_tasks = 0
    for name, job in jobs.items():
        rows = [line.split("|") for line in farm.sql(
            f"SELECT first_pass, last_pass, state, passes_done, attempt FROM tasks WHERE job_id = "
            f"'{job['id']}' ORDER BY first_pass").split()]
        tasks = [(int(f), int(l), s, int(p), int(a)) for f, l, s, p, a in rows]
        passes = job["passes_done"]
        merged = [t for t in tasks if t[0] < passes]
        assert all(t[2] == "done" and t[4] >= 1 for t in merged), (name, tasks)
        assert sum(min(t[3], passes - t[0]) for t in merged) == passes, (name, passes, tasks)
        if job["settings"].get("target_error", 0) == 0:
            assert all(t[2] == "done" for t in tasks) and sum(t[3] for t in tasks) == passes, \
                (name, passes, tasks)
        done = [t for t in tasks if t[2] == "done"]
        assert job["stats"]["tasks"] == len(done), (name, job["stats"], tasks)
        done_tasks += len(done)
    # Each hand-in that merged counted once on its worker, the killed ones' rows included.
    counted = farm.sql("SELECT COALESCE(SUM(tasks_done), 0) FROM workers")
    assert int(counted) == done_tasks, (counted, done_tasks)


def test_jobs_survive_killed_workers_api_and_a_postgres_restart(farm, postgres, start_server,
                                                                caustic_bin, tmp_path):
    seed = int(os.environ.get("CAUSTIC_FAULT_SEED", random.SystemRandom().randrange(2**32)))
    rng = random.Random(seed)
    plan = schedule(rng)
    print(f"\nfault seed {seed} (CAUSTIC_FAULT_SEED={seed} replays it); schedule: {plan}")
    began = time.monotonic()

    api, workers = farm(workers=3, worker_args=WORKER_ARGS)
    single = start_server("--threads", "1")
    state = Farm(api, workers, postgres, start_server,
                 lambda: Worker(caustic_bin, api.store, str(tmp_path), "--threads", "1",
                                *WORKER_ARGS))
    bodies = fault_jobs()
    # One process renders the same jobs meanwhile, unsplit (priority and task_passes are the
    # scale-out's).
    references = {name: submit_ok(single, {"scene": body["scene"],
                                           "settings": body["settings"]})["id"]
                  for name, body in bodies}
    for name, body in bodies:
        state.ids[name] = submit_ok(api, body)["id"]
    try:
        for i, (kind, gap) in enumerate(plan):
            time.sleep(gap)
            if kind == "worker":
                did = state.kill_worker(rng)
            elif kind == "api":
                did = state.kill_api()
            else:
                did = state.restart_postgres(rng)
            print(f"  {time.monotonic() - began:6.1f} s  fault {i + 1}: {did}")
            state.watch()
        wait_all(state)
        print(f"  {time.monotonic() - began:6.1f} s  every split job ended: {state.seen}")

        jobs = {name: state.ask(f"/api/jobs/{job_id}") for name, job_id in state.ids.items()}
        for name, job in jobs.items():
            assert job["state"] == "succeeded", (name, job)
            assert state.seen[job["id"]][-1] == "succeeded" and \
                state.seen[job["id"]].count("succeeded") == 1, (name, state.seen[job["id"]])
            assert job["finished_at"] == state.finished[job["id"]], (name, job)
        check_database(state, jobs)
        for name, job_id in references.items():
            whole = single.wait(job_id, ENDED, deadline=180)
            assert whole["state"] == "succeeded", (name, whole)
            job = jobs[name]
            assert job["passes_done"] == whole["passes_done"], (name, job, whole)
            split = state.ask_bytes(f"/api/jobs/{job['id']}/image.exr")
            r = single.get(f"/api/jobs/{job_id}/image.exr")
            assert r.status_code == 200, r.text
            assert split == r.content, f"{name}: the split job's image.exr differs"
        print(f"  {time.monotonic() - began:6.1f} s  images bit-identical to one process's")
    except BaseException:
        print("worker logs:\n" + "\n".join(w.log()[-1000:] for w in state.workers))
        raise
    finally:
        state.stop_replacements()


def test_a_postgres_outage_is_503_and_the_farm_comes_back(farm, postgres):
    """PostgreSQL down for longer than the store's reconnecting (about 3 s): the API answers 503
    with Retry-After, not 500; a worker stopped meanwhile still exits cleanly; once PostgreSQL is
    back, the job finishes with no task counted against a worker."""
    api, (worker,) = farm(workers=1, worker_args=WORKER_ARGS)
    job = submit_ok(api, {"scene": tiny_scene(width=64, height=64), "task_passes": 8,
                          "settings": {"spp": 64 * 32, "spp_per_pass": 64}})
    api.wait(job["id"], ("running",), deadline=30)
    postgres.down()
    try:
        r = api.get(f"/api/jobs/{job['id']}")
        assert r.status_code == 503 and r.headers["Retry-After"] == "5", r.text
        assert r.json()["status"] == 503 and "cannot be reached" in r.json()["detail"], r.text
        worker.stop()
        assert worker.proc.returncode == 0, worker.log()
    finally:
        postgres.restart()
    replacement = Worker(worker.args[0], api.store, worker.workdir, "--threads", "1",
                         *WORKER_ARGS).start()
    try:
        done = api.wait(job["id"], ENDED, deadline=120)
        assert done["state"] == "succeeded" and done["passes_done"] == 32, done
        database = api.store.rsplit("/", 1)[1]
        assert postgres.psql("SELECT COUNT(*) FROM task_failures", database=database).strip() \
            == "0"
    finally:
        replacement.stop()
