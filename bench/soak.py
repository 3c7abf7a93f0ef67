#!/usr/bin/env python3
"""Soak: a long mixed load against a PostgreSQL farm while its processes are killed, stopped and
restarted on a schedule (bench/README.md, "Soak"; docs/operations.md, "Timeouts and limits").

Starts a throwaway PostgreSQL cluster (tests/support/postgres.sh, 127.0.0.1), one API process
(`caustic serve --store ... --workers 0`) and two `caustic worker --threads 1` processes. For
--minutes, six kinds of clients run at once:

- jobs: a split job (task_passes 2) every --job-seconds, cycling through a few bodies (path,
  photon and ppm on a small scene, each with two seeds);
- uploads: an OBJ every 20 s (the teapot, made distinct by a comment), then a job drawing it;
- event streams: 3 clients following a recent job's /events until it ends;
- slow clients: 40 connections from 127.0.0.2 and 127.0.0.3 sending a header byte every 3 s,
  opened again whenever the server closes them;
- pollers: GET /healthz and GET /api/jobs/{id} of a random recent job, each every 100 ms, timed.

Every --cycle seconds the schedule runs again: a worker SIGKILLed (and started again 5 s later), the
other SIGSTOPped for 20 s (past its 10 s lease), PostgreSQL restarted; in the first cycle, the API
process SIGKILLed and started again on the same port (its next process lives the rest of the run). Then the load stops, every job is waited for, and each
distinct body is rendered once by a SQLite `caustic serve --threads 1`: every succeeded job's
image.exr must be those very bytes (a pass lost or counted twice changes them).

Prints: requests served by kind with their statuses, p50/p99/max latency of /healthz and GET
/api/jobs/{id} (those that got an answer; the ones that found no server while the API restarted
are counted apart), jobs succeeded, failed (with reasons) and wrong, and the resident memory of
each process at its start and end. Standard-library Python only.

usage: bench/soak.py [--binary PATH] [--minutes M] [--cycle S] [--job-seconds S] [--smoke]
"""

import argparse
import hashlib
import http.client
import json
import os
import random
import shlex
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request

from scale_out import POSTGRES_SH, REPO, Cluster, Process, serve

TEAPOT = os.path.join(REPO, "assets", "meshes", "teapot.obj")
SCENE = {
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40,
               "width": 40, "height": 40},
    "materials": {
        "white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
        "lamp": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5], "emission": [4, 4, 4]},
    },
    "shapes": [
        {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.3, "material": "lamp"},
        {"type": "quad", "origin": [-1, -1, -1], "u": [2, 0, 0], "v": [0, 2, 0],
         "material": "white"},
    ],
}
SETTINGS = [
    {"integrator": "path", "spp": 32, "spp_per_pass": 2},
    {"integrator": "photon", "photons": 4000, "spp": 8, "spp_per_pass": 1},
    {"integrator": "ppm", "photons": 4000, "spp": 8, "spp_per_pass": 1},
]


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--binary", default=os.path.join(REPO, "build", "cli", "caustic"))
    p.add_argument("--minutes", type=float, default=30)
    p.add_argument("--cycle", type=float, default=240, help="seconds between schedule repeats")
    p.add_argument("--job-seconds", type=float, default=2.0, help="seconds between jobs")
    p.add_argument("--smoke", action="store_true",
                   help="about a minute, one cycle compressed: checks that it runs (CTest)")
    args = p.parse_args()
    if args.smoke:
        args.minutes, args.cycle, args.job_seconds = 0.75, 40, 3.0
    return args


def percentile(values, q):
    if not values:
        return float("nan")
    s = sorted(values)
    return s[min(len(s) - 1, int(q * len(s)))]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def rss(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return None


class Farm:
    """The API process and the workers, each started again as the schedule needs."""

    def __init__(self, binary, folder, store):
        self.binary, self.folder, self.store = binary, folder, store
        self.port = free_port()
        self.base = f"http://127.0.0.1:{self.port}"
        self.instances = []  # [role, pid, first rss, last rss, peak rss, [(minute, rss)]]
        self.start = time.monotonic()
        self.lock = threading.Lock()
        self.api = self.start_api()
        self.workers = [self.start_worker(i) for i in range(2)]

    def track(self, role, proc):
        with self.lock:
            self.instances.append([role, proc.proc.pid, None, None, 0, []])
        return proc

    def start_api(self):
        # The same data folder and port each time: clients see one service, restarted.
        p = Process([self.binary, "serve", "--host", "127.0.0.1", "--port", str(self.port),
                     "--data", os.path.join(self.folder, "api"), "--store", self.store,
                     "--workers", "0"], self.folder, f"api-{len(self.instances)}",
                    r"serving on (http://127\.0\.0\.1:\d+)/")
        return self.track("api", p)

    def start_worker(self, i):
        p = Process([self.binary, "worker", "--store", self.store, "--threads", "1"], self.folder,
                    f"worker{i}-{len(self.instances)}", r"caustic: worker rendering")
        return self.track(f"worker {i}", p)

    def sample_memory(self):
        with self.lock:
            for inst in self.instances:
                value = rss(inst[1])
                if value is None:
                    continue
                inst[2] = inst[2] or value
                inst[3] = value
                inst[4] = max(inst[4], value)
                inst[5].append(((time.monotonic() - self.start) / 60, value))

    def stop(self):
        for p in [self.api, *self.workers]:
            p.stop()


class Stats:
    def __init__(self):
        self.lock = threading.Lock()
        self.counts = {}  # kind -> {status -> n}
        self.latency = {"healthz": [], "job": []}
        self.jobs = {}  # id -> body key
        self.bodies = {}  # body key -> body
        self.stream_events = 0

    def count(self, kind, status):
        with self.lock:
            by = self.counts.setdefault(kind, {})
            by[status] = by.get(status, 0) + 1


def request(base, method, path, body=None, data=None, media="application/json", timeout=30):
    """(status, parsed JSON or None); status is 'no server' or 'timeout' without an answer."""
    if body is not None:
        data = json.dumps(body).encode()
    req = urllib.request.Request(base + path, data=data, method=method,
                                 headers={"Content-Type": media})
    try:
        with urllib.request.urlopen(req, timeout=timeout) as r:
            raw = r.read()
            status = r.status
    except urllib.error.HTTPError as e:
        raw, status = e.read(), e.code
    except (ConnectionError, urllib.error.URLError) as e:
        reason = getattr(e, "reason", e)
        return ("timeout" if isinstance(reason, socket.timeout) else "no server"), None
    except (socket.timeout, TimeoutError):
        return "timeout", None
    try:
        return status, json.loads(raw)
    except ValueError:
        return status, None


def body_key(body):
    return hashlib.sha256(json.dumps(body, sort_keys=True).encode()).hexdigest()[:12]


def submit(farm, stats, body, key=None):
    """Submits `body`; its image must match the others of `key` (by default, the same body)."""
    status, job = request(farm.base, "POST", "/api/jobs", body)
    stats.count("POST /api/jobs", status)
    if status != 202:
        return None
    key = key or body_key(body)
    with stats.lock:
        stats.bodies.setdefault(key, body)
        stats.jobs[job["id"]] = key
    return job["id"]


def recent_job(stats):
    with stats.lock:
        ids = list(stats.jobs)
    return random.choice(ids[-20:]) if ids else None


def job_client(farm, stats, stop, args):
    n = 0
    while not stop.wait(args.job_seconds):
        settings = {**SETTINGS[n % len(SETTINGS)], "seed": (n // len(SETTINGS)) % 2}
        submit(farm, stats, {"scene": SCENE, "settings": settings, "task_passes": 2})
        n += 1


def upload_client(farm, stats, stop):
    with open(TEAPOT, "rb") as f:
        teapot = f.read()
    n = 0
    while not stop.wait(20):
        n += 1
        data = f"# soak upload {n} {time.time()}\n".encode() + teapot
        status, asset = request(farm.base, "POST", "/api/assets?name=teapot.obj", data=data,
                                media="model/obj", timeout=60)
        stats.count("POST /api/assets", status)
        if status not in (200, 201):
            continue
        scene = json.loads(json.dumps(SCENE))
        scene["shapes"].insert(1, {"type": "mesh", "asset": asset["id"], "material": "white",
                                   "transform": {"scale": 0.3, "translate": [0, -0.6, 0]}})
        # The asset's id differs each time, its triangles do not: one reference serves them all.
        body = {"scene": scene, "settings": {**SETTINGS[0], "seed": 0}, "task_passes": 2}
        submit(farm, stats, body, key="upload")


def stream_client(farm, stats, stop):
    while not stop.is_set():
        job_id = recent_job(stats)
        if not job_id:
            stop.wait(1)
            continue
        try:
            conn = http.client.HTTPConnection("127.0.0.1", farm.port, timeout=30)
            conn.request("GET", f"/api/jobs/{job_id}/events")
            r = conn.getresponse()
            stats.count("GET /api/jobs/{id}/events", r.status)
            if r.status == 200:
                while not stop.is_set():
                    line = r.readline()
                    if not line:
                        break
                    if line.startswith(b"event:"):
                        with stats.lock:
                            stats.stream_events += 1
                        if line.strip() in (b"event: end", b"event: deleted"):
                            break
            conn.close()
        except (OSError, http.client.HTTPException):
            stats.count("GET /api/jobs/{id}/events", "no server")
        # A job that has ended answers at once: the next stream a second later.
        stop.wait(1)


def slow_clients(farm, stats, stop):
    """40 connections that send a request head one byte every 3 s."""
    head = b"GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"
    conns = []
    while not stop.wait(3):
        conns = [c for c in conns if c[0] is not None]
        while len(conns) < 40:
            source = "127.0.0.2" if len(conns) % 2 else "127.0.0.3"
            try:
                s = socket.create_connection(("127.0.0.1", farm.port), timeout=1,
                                             source_address=(source, 0))
                conns.append([s, 0])
                stats.count("slow connection", "opened")
            except OSError:
                stats.count("slow connection", "refused or no server")
                break
        for c in conns:
            try:
                c[0].send(head[c[1] % len(head):c[1] % len(head) + 1])
                c[1] += 1
            except OSError:
                stats.count("slow connection", "closed by the server")
                c[0].close()
                c[0] = None
    for c in conns:
        if c[0] is not None:
            c[0].close()


def poller(farm, stats, stop, kind):
    while not stop.wait(0.1):
        path = "/healthz"
        if kind == "job":
            job_id = recent_job(stats)
            if not job_id:
                continue
            path = f"/api/jobs/{job_id}"
        start = time.perf_counter()
        status, _ = request(farm.base, "GET", path, timeout=10)
        elapsed = time.perf_counter() - start
        stats.count("GET " + ("/healthz" if kind == "healthz" else "/api/jobs/{id}"), status)
        if isinstance(status, int):
            with stats.lock:
                stats.latency[kind].append(elapsed)


def schedule(farm, cluster, stop, cycle, log):
    """The faults, at fixed fractions of each cycle."""
    start = time.monotonic()
    events = [(0.15, "SIGKILL worker 0"), (0.35, "SIGSTOP worker 1"), (0.55, "restart PostgreSQL"),
              (0.8, "SIGKILL the API process")]
    n = 0
    while not stop.is_set():
        # The API process is killed in the first cycle only: its next one lives the rest of the
        # run, long enough to show whether its memory stays flat.
        for fraction, what in events if n == 0 else events[:-1]:
            at = start + n * cycle + fraction * cycle
            if stop.wait(max(0, at - time.monotonic())):
                return
            log.append((round(time.monotonic() - start, 1), what))
            if what == "SIGKILL worker 0":
                os.killpg(farm.workers[0].proc.pid, signal.SIGKILL)
                farm.workers[0].proc.wait()
                stop.wait(5)
                farm.workers[0] = farm.start_worker(0)
            elif what == "SIGSTOP worker 1":
                os.killpg(farm.workers[1].proc.pid, signal.SIGSTOP)
                stop.wait(20)
                os.killpg(farm.workers[1].proc.pid, signal.SIGCONT)
            elif what == "restart PostgreSQL":
                subprocess.run(["bash", POSTGRES_SH, "restart", cluster.folder], check=True,
                               capture_output=True, timeout=120)
            else:
                os.killpg(farm.api.proc.pid, signal.SIGKILL)
                farm.api.proc.wait()
                farm.api = farm.start_api()
        n += 1


def wait_for_jobs(farm, stats, deadline):
    """Every job's final state (a job still running at `deadline` is reported as such)."""
    with stats.lock:
        ids = dict(stats.jobs)
    final = {}
    end = time.monotonic() + deadline
    for job_id in ids:
        while True:
            status, job = request(farm.base, "GET", f"/api/jobs/{job_id}")
            if status == 200 and job["state"] in ("succeeded", "failed", "cancelled"):
                final[job_id] = job
                break
            if time.monotonic() > end:
                final[job_id] = job if status == 200 else {"state": f"unknown ({status})"}
                break
            time.sleep(0.2)
    return final


def image(base, job_id):
    with urllib.request.urlopen(f"{base}/api/jobs/{job_id}/image.exr", timeout=60) as r:
        return r.read()


def check_images(binary, folder, farm, stats, final):
    """Each distinct body once on one SQLite process; every succeeded job's EXR must match."""
    single, base = serve(binary, folder, "--threads", "1")
    wrong, checked = [], 0
    try:
        references = {}
        for key, body in stats.bodies.items():
            if key == "upload":
                # The reference uploads the same mesh bytes as the first upload job drew.
                continue
            _, job = request(base, "POST", "/api/jobs", body)
            references[key] = job["id"]
        for key, job_id in references.items():
            while request(base, "GET", f"/api/jobs/{job_id}")[1]["state"] not in (
                    "succeeded", "failed", "cancelled"):
                time.sleep(0.1)
            references[key] = hashlib.sha256(image(base, job_id)).hexdigest()
        for job_id, job in final.items():
            key = stats.jobs[job_id]
            if job["state"] != "succeeded" or key not in references:
                continue
            checked += 1
            if hashlib.sha256(image(farm.base, job_id)).hexdigest() != references[key]:
                wrong.append(job_id)
        # Upload jobs: each must match the first (the same triangles, another asset id).
        uploads = [j for j, job in final.items()
                   if stats.jobs[j] == "upload" and job["state"] == "succeeded"]
        if uploads:
            first = hashlib.sha256(image(farm.base, uploads[0])).hexdigest()
            for job_id in uploads:
                checked += 1
                if hashlib.sha256(image(farm.base, job_id)).hexdigest() != first:
                    wrong.append(job_id)
    finally:
        single.stop()
    return checked, wrong


def main():
    args = parse_args()
    if not os.access(args.binary, os.X_OK):
        sys.exit(f"soak: no caustic binary at {args.binary} (build it, or --binary)")
    binary = os.path.abspath(args.binary)
    if not os.access(os.path.join(os.environ.get("CAUSTIC_PG_BIN", "/usr/lib/postgresql/15/bin"),
                                  "initdb"), os.X_OK):
        print("soak: no PostgreSQL server binaries: skipped", file=sys.stderr)
        sys.exit(77)
    command = " ".join(shlex.quote(a) for a in sys.argv)
    folder = tempfile.mkdtemp(prefix="caustic-soak-", dir="/tmp")
    cluster = Cluster()
    farm = None
    stats, stop, log = Stats(), threading.Event(), []
    try:
        farm = Farm(binary, folder, cluster.create_database())
        farm.sample_memory()
        threads = [threading.Thread(target=job_client, args=(farm, stats, stop, args)),
                   threading.Thread(target=upload_client, args=(farm, stats, stop)),
                   threading.Thread(target=slow_clients, args=(farm, stats, stop)),
                   threading.Thread(target=poller, args=(farm, stats, stop, "healthz")),
                   threading.Thread(target=poller, args=(farm, stats, stop, "job")),
                   threading.Thread(target=schedule, args=(farm, cluster, stop, args.cycle, log))]
        threads += [threading.Thread(target=stream_client, args=(farm, stats, stop))
                    for _ in range(3)]
        for t in threads:
            t.daemon = True
            t.start()
        end = time.monotonic() + args.minutes * 60
        while time.monotonic() < end:
            time.sleep(min(10, max(0, end - time.monotonic())))
            farm.sample_memory()
            print(f"soak: {len(stats.jobs)} jobs submitted, {len(log)} faults", file=sys.stderr)
        stop.set()
        for t in threads:
            t.join(timeout=60)
        final = wait_for_jobs(farm, stats, deadline=600)
        farm.sample_memory()
        checked, wrong = check_images(binary, folder, farm, stats, final)
    finally:
        stop.set()
        if farm:
            farm.stop()
        cluster.stop()
    report(args, command, stats, final, log, farm, checked, wrong)
    if wrong or any(j["state"] != "succeeded" for j in final.values()):
        sys.exit(1)


def report(args, command, stats, final, log, farm, checked, wrong):
    mib = 1 << 20
    print(f"command: {command}")
    print(f"machine: nproc {os.cpu_count()}; load average {open('/proc/loadavg').read()[:14]}")
    print(f"run: {args.minutes:g} min, a fault schedule every {args.cycle:g} s; "
          f"{len(log)} faults: " + ", ".join(f"{t} s {w}" for t, w in log))
    print()
    print("| requests | answers by status | total |")
    print("|---|---|---:|")
    for kind, by in sorted(stats.counts.items()):
        print(f"| {kind} | " + ", ".join(f"{s}: {n}" for s, n in sorted(by.items(), key=str)) +
              f" | {sum(by.values())} |")
    print(f"\nevent-stream events received: {stats.stream_events}")
    print()
    print("| latency (answered) | n | p50 ms | p99 ms | max ms |")
    print("|---|---:|---:|---:|---:|")
    for kind, name in (("healthz", "GET /healthz"), ("job", "GET /api/jobs/{id}")):
        v = stats.latency[kind]
        print(f"| {name} | {len(v)} | {1000 * percentile(v, 0.5):.1f} | "
              f"{1000 * percentile(v, 0.99):.1f} | {1000 * max(v, default=0):.1f} |")
    states = {}
    for job in final.values():
        states[job["state"]] = states.get(job["state"], 0) + 1
    print(f"\njobs: {len(final)} submitted; " +
          ", ".join(f"{s}: {n}" for s, n in sorted(states.items())))
    for job_id, job in final.items():
        if job["state"] != "succeeded":
            print(f"  {job_id} {job['state']}: {job.get('error')}")
    print(f"images: {checked} succeeded jobs' EXR compared with one process's render, "
          f"{len(wrong)} differ" + (": " + ", ".join(wrong) if wrong else ""))
    print()
    print("| process | pid | resident MiB at start | at end | peak |")
    print("|---|---:|---:|---:|---:|")
    for role, pid, first, last, peak, _ in farm.instances:
        if first:
            print(f"| {role} | {pid} | {first / mib:.1f} | {last / mib:.1f} | {peak / mib:.1f} |")
    # The processes that lived 10 minutes or more: their resident memory every 5 minutes, to tell
    # a leak (a steady climb) from a warm-up (a rise that levels off).
    print()
    for role, pid, first, _, _, samples in farm.instances:
        if samples and samples[-1][0] - samples[0][0] >= 10:
            points, next_minute = [], samples[0][0]
            for minute, value in samples:
                if minute >= next_minute:
                    points.append(f"{minute:.0f} min {value / mib:.1f}")
                    next_minute = minute + 5
            points.append(f"{samples[-1][0]:.0f} min {samples[-1][1] / mib:.1f}")
            print(f"{role} (pid {pid}) resident MiB: " + ", ".join(points))


if __name__ == "__main__":
    main()
