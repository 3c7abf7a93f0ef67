#!/usr/bin/env python3
"""Crash test of `caustic serve` (issue 6, acceptance item 2): durability under SIGKILL.

Starts the real server on 127.0.0.1 with a fixed data folder and a fixed free port, submits small
render jobs (each with an Idempotency-Key), SIGKILLs the server at random points while they render
and restarts it on the same data folder, 20 times in a row, then lets every job finish. Asserts:

- every submitted job exists exactly once (no duplicates, none lost), and a retried POST with the
  same Idempotency-Key names the same job;
- every job succeeded, once: all its passes, its state never left `succeeded` once there, its
  finished_at never changed, its attempt never went down, its passes never went back by more than
  the one pass a client may see before it is checkpointed;
- every job's image.exr holds exactly the pixels of an uninterrupted `caustic render` of the same
  scene, settings and seed (the EXR bytes but for its capDate, and `idiff` with zero thresholds);
- no temporary file of a killed writer is left in the job folders.

A SIGKILL is not the job's fault: kills must never fail a job as "stalled", however often they
land before a pass finishes (job "heavy-ppm-spheres" has long photon-tracing passes for that).

Standard library only (no venv needed). Reproduce a run with CAUSTIC_CRASH_SEED=<printed seed>.

usage: crash_test.py [CAUSTIC_BINARY]   (default: build/cli/caustic, or $CAUSTIC_CLI)
environment: CAUSTIC_CRASH_SEED (kill schedule), CAUSTIC_CRASH_KILLS (default 20),
             CAUSTIC_CRASH_WORKERS (default 2), CAUSTIC_CRASH_KEEP=1 keeps the temporary folder,
             CAUSTIC_CRASH_DEADLINE (seconds for the whole test, default 360)
"""

import ctypes
import http.client
import json
import os
import random
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
T0 = time.monotonic()


def log(*args):
    print(f"[{time.monotonic() - T0:7.2f}s]", *args, flush=True)


class TestFailure(Exception):
    pass


# --- The jobs -------------------------------------------------------------------------------------
# Small renders of 8-16 passes, a few seconds each, far below the server's time limit. Job "heavy"
# has long photon-tracing passes, so that some kills land before any pass of an attempt finishes.
JOBS = [
    ("path-spheres", "cornell-spheres", 64, {"integrator": "path", "spp": 288, "spp_per_pass": 24, "seed": 101}),
    ("heavy-ppm-spheres", "cornell-spheres", 48, {"integrator": "ppm", "photons": 400000, "spp": 8, "spp_per_pass": 1, "seed": 102}),
    ("photon-spheres", "cornell-spheres", 48, {"integrator": "photon", "photons": 100000, "spp": 12, "spp_per_pass": 1, "seed": 103}),
    ("path-box", "cornell-box", 64, {"integrator": "path", "spp": 320, "spp_per_pass": 20, "seed": 104}),
    ("ppm-box", "cornell-box", 48, {"integrator": "ppm", "photons": 100000, "spp": 16, "spp_per_pass": 1, "seed": 105}),
    ("photon-box", "cornell-box", 64, {"integrator": "photon", "photons": 150000, "spp": 10, "spp_per_pass": 1, "seed": 106}),
    ("path-spheres-48", "cornell-spheres", 48, {"integrator": "path", "spp": 768, "spp_per_pass": 64, "seed": 107}),
    ("ppm-spheres", "cornell-spheres", 64, {"integrator": "ppm", "photons": 100000, "spp": 12, "spp_per_pass": 1, "seed": 108}),
]
UP_FRONT = 5  # submitted before the first kill; the rest go in during the kill rounds


def scene_object(name, size):
    with open(os.path.join(ROOT, "scenes", name + ".json")) as f:
        scene = json.load(f)
    scene["camera"]["width"] = size
    scene["camera"]["height"] = size
    return scene


# --- HTTP -----------------------------------------------------------------------------------------
class Http:
    def __init__(self, port):
        self.base = f"http://127.0.0.1:{port}"

    def request(self, method, path, body=None, headers=None, timeout=10):
        data = None if body is None else body.encode()
        req = urllib.request.Request(self.base + path, data=data, method=method)
        for k, v in (headers or {}).items():
            req.add_header(k, v)
        if data is not None:
            req.add_header("Content-Type", "application/json")
        try:
            with urllib.request.urlopen(req, timeout=timeout) as r:
                return r.status, r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.read()

    def json(self, method, path, body=None, headers=None, timeout=10):
        status, raw = self.request(method, path, body, headers, timeout)
        return status, (json.loads(raw) if raw else None)


# --- The server -----------------------------------------------------------------------------------
def die_with_parent():
    # The server must not outlive this script, whatever kills it (a CTest timeout, Ctrl-C).
    try:
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except Exception:
        pass


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Server:
    def __init__(self, binary, data, port, workers, logdir):
        self.binary, self.data, self.port, self.workers = binary, data, port, workers
        self.logdir = logdir
        self.proc = None
        self.starts = 0
        self.http = Http(port)

    def log_path(self, n):
        return os.path.join(self.logdir, f"server-{n:02d}.log")

    def start(self, timeout=30):
        deadline = time.monotonic() + timeout
        while True:
            self.starts += 1
            out = open(self.log_path(self.starts), "wb")
            self.proc = subprocess.Popen(
                [self.binary, "serve", "--port", str(self.port), "--data", self.data,
                 "--workers", str(self.workers)],
                stdout=out, stderr=subprocess.STDOUT, preexec_fn=die_with_parent)
            out.close()
            while time.monotonic() < deadline and self.proc.poll() is None:
                try:
                    if self.http.request("GET", "/healthz", timeout=2)[0] == 200:
                        return
                except (OSError, http.client.HTTPException):
                    pass
                time.sleep(0.02)
            if self.proc.poll() is None:
                self.kill()
                raise TestFailure(f"the server did not answer /healthz within {timeout} s")
            if time.monotonic() >= deadline:
                raise TestFailure("the server exits at start-up: " + self.tail(self.starts))
            time.sleep(0.2)  # e.g. the port is briefly not free again: retry

    def kill(self):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGKILL)
        if self.proc:
            self.proc.wait()

    def stop(self):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.kill()

    def tail(self, n, lines=20):
        try:
            with open(self.log_path(n), errors="replace") as f:
                return "".join(f.readlines()[-lines:])
        except OSError:
            return ""


# --- Observing the jobs while they render ---------------------------------------------------------
class Observer:
    """Polls GET /api/jobs while the server is up and checks that nothing goes backwards."""

    def __init__(self, api):
        self.http = api
        self.seen = {}  # id -> {"state", "attempt", "passes", "finished_at"}
        self.problems = []
        self.pass_regressions = 0
        self.max_attempt = {}
        self.stop = threading.Event()
        self.lock = threading.Lock()

    def observe(self, job):
        with self.lock:
            jid = job["id"]
            prev = self.seen.get(jid)
            now = {"state": job["state"], "attempt": job["attempt"],
                   "passes": job["passes_done"], "finished_at": job["finished_at"]}
            if prev:
                if now["attempt"] < prev["attempt"]:
                    self.problems.append(f"{jid}: attempt went from {prev['attempt']} to {now['attempt']}")
                if prev["state"] in ("succeeded", "failed", "cancelled") and (
                        now["state"] != prev["state"] or now["finished_at"] != prev["finished_at"]):
                    self.problems.append(f"{jid}: was {prev['state']} (finished {prev['finished_at']}), "
                                         f"then {now['state']} (finished {now['finished_at']})")
                if now["passes"] < prev["passes"]:
                    # Passes shown are those in the store, and a resumed job records its
                    # checkpoint's passes before it renders more: progress never goes back.
                    self.problems.append(f"{jid}: passes_done went from {prev['passes']} to {now['passes']}")
                    self.pass_regressions += 1
            self.seen[jid] = now
            self.max_attempt[jid] = max(self.max_attempt.get(jid, 0), now["attempt"])

    def poll_once(self):
        try:
            status, body = self.http.json("GET", "/api/jobs?limit=100", timeout=3)
        except (OSError, ValueError, http.client.HTTPException):
            return  # the server is down, or went down under the request
        if status == 200:
            for job in body["jobs"]:
                self.observe(job)

    def run(self):
        while not self.stop.is_set():
            self.poll_once()
            time.sleep(0.1)


# --- Comparing images -----------------------------------------------------------------------------
def exr_bytes_without_dates(path):
    """The EXR file's bytes with the values of its date attributes blanked (OpenEXR writes the
    time of writing in capDate); everything else, the pixels included, must match exactly."""
    with open(path, "rb") as f:
        data = bytearray(f.read())
    if data[:4] != b"\x76\x2f\x31\x01":
        raise TestFailure(f"{path} is not an OpenEXR file")
    pos = 8
    while data[pos] != 0:
        end = data.index(0, pos)
        name = bytes(data[pos:end])
        tend = data.index(0, end + 1)
        (size,) = struct.unpack_from("<i", data, tend + 1)
        value = tend + 5
        if name in (b"capDate", b"DateTime"):
            data[value:value + size] = bytes(size)
        pos = value + size
    return bytes(data)


def same_pixels(a, b):
    """(exact, detail): EXR bytes (dates blanked) and idiff's decoded floats, zero tolerance."""
    exact_bytes = exr_bytes_without_dates(a) == exr_bytes_without_dates(b)
    idiff = shutil.which("idiff")
    if not idiff:
        return exact_bytes, "bytes " + ("equal" if exact_bytes else "differ") + " (no idiff)"
    r = subprocess.run([idiff, "-fail", "0", "-warn", "0", a, b], capture_output=True, text=True)
    exact_pixels = r.returncode == 0
    detail = f"bytes {'equal' if exact_bytes else 'differ'}, idiff {'PASS' if exact_pixels else 'FAIL'}"
    if not exact_pixels:
        detail += "\n" + r.stdout.strip()
    return exact_bytes and exact_pixels, detail


def setting_arg(key, value):
    return f"{key}={value if isinstance(value, str) else json.dumps(value)}"


# --- The test -------------------------------------------------------------------------------------
def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else os.environ.get(
        "CAUSTIC_CLI", os.path.join(ROOT, "build", "cli", "caustic"))
    seed = int(os.environ.get("CAUSTIC_CRASH_SEED") or random.SystemRandom().randrange(1, 10**9))
    kills_wanted = int(os.environ.get("CAUSTIC_CRASH_KILLS", "20"))
    workers = int(os.environ.get("CAUSTIC_CRASH_WORKERS", "2"))
    deadline = T0 + float(os.environ.get("CAUSTIC_CRASH_DEADLINE", "360"))
    rng = random.Random(seed)
    tmp = tempfile.mkdtemp(prefix="caustic-crash-")
    data = os.path.join(tmp, "data")
    port = free_port()
    log(f"seed {seed} (CAUSTIC_CRASH_SEED={seed} reproduces the kill schedule); {kills_wanted} kills; "
        f"{workers} workers; binary {binary}; data {data}; port {port}; nproc {os.cpu_count()}, "
        f"load {os.getloadavg()[0]:.2f}")

    server = Server(binary, data, port, workers, tmp)
    api = server.http
    observer = Observer(api)
    poller = threading.Thread(target=observer.run, daemon=True)
    ok = False
    try:
        server.start()
        poller.start()

        # key -> {"name", "body", "id" or None, "uncertain": the POST may have been lost}
        submissions = {}
        order = [j[0] for j in JOBS]
        scenes = {}

        def submit(name):
            entry = submissions.get(name)
            if entry is None:
                _, scene, size, settings = next(j for j in JOBS if j[0] == name)
                scenes[name] = scene_object(scene, size)
                body = json.dumps({"scene": scenes[name], "settings": settings}, sort_keys=True)
                entry = submissions[name] = {"key": f"crash-{seed}-{name}", "body": body,
                                             "id": None, "uncertain": True, "posts": 0}
            entry["posts"] += 1
            try:
                status, resp = api.json("POST", "/api/jobs", entry["body"],
                                         {"Idempotency-Key": entry["key"]}, timeout=15)
            except (OSError, ValueError, http.client.HTTPException) as e:  # died under the request
                entry["uncertain"] = True
                return f"lost ({type(e).__name__})"
            if status != 202:
                raise TestFailure(f"POST {name}: {status} {resp}")
            if entry["id"] and entry["id"] != resp["id"]:
                raise TestFailure(f"POST {name} again with key {entry['key']}: job {resp['id']}, "
                                  f"the first answer named {entry['id']}")
            entry["id"] = resp["id"]
            entry["uncertain"] = False
            return resp["id"]

        for name in order[:UP_FRONT]:
            log(f"submit {name}: {submit(name)}")

        # The kill rounds. Most delays let a pass or a few finish; some are short (kills during
        # start-up, claiming, photon tracing); some land right under a POST.
        kills = kills_on_running = 0
        late = list(order[UP_FRONT:])
        for round_ in range(1, kills_wanted + 1):
            if time.monotonic() > deadline - 240:
                raise TestFailure(f"out of time after {kills} kills")
            for entry_name, entry in submissions.items():
                if entry["uncertain"]:
                    log(f"  resubmit {entry_name} (same key): {submit(entry_name)}")
            u = rng.random()
            delay = rng.uniform(0.05, 0.6) if u < 0.3 else rng.uniform(0.6, 3.5)
            post_thread = None
            if late and rng.random() < 0.5:
                # Submit under the kill: the POST may be answered, committed but unanswered, or lost.
                name = late.pop(0)
                delay = rng.uniform(0.0, 0.08)
                result = {}
                post_thread = threading.Thread(target=lambda n=name: result.setdefault(n, submit(n)))
                post_thread.start()
            time.sleep(delay)
            observer.poll_once()
            running = sum(1 for j in observer.seen.values() if j["state"] == "running")
            server.kill()
            kills += 1
            kills_on_running += running > 0
            if post_thread:
                post_thread.join()
                log(f"kill {round_:2d} after {delay:.2f} s, {running} running, under POST {name}: "
                    f"{result.get(name)}")
            else:
                log(f"kill {round_:2d} after {delay:.2f} s, {running} running")
            server.start()
        for name in late:
            log(f"submit {name}: {submit(name)}")
        for entry_name, entry in submissions.items():
            if entry["uncertain"]:
                log(f"resubmit {entry_name} (same key): {submit(entry_name)}")
        if any(e["uncertain"] for e in submissions.values()):
            raise TestFailure("a POST still fails with the server up")

        # Let everything finish.
        log("kills done; waiting for every job to end")
        while True:
            observer.poll_once()
            states = [observer.seen.get(e["id"], {}).get("state") for e in submissions.values()]
            if all(s in ("succeeded", "failed", "cancelled") for s in states):
                break
            if time.monotonic() > deadline - 120:
                raise TestFailure(f"jobs did not finish in time: {states}")
            time.sleep(0.25)
        observer.stop.set()
        poller.join()
        log("every job ended")

        failures = []
        # Exactly once: the listing holds each submitted job once, and nothing else.
        listed = []
        cursor = None
        while True:
            status, page = api.json("GET", "/api/jobs?limit=100" + (f"&cursor={cursor}" if cursor else ""))
            listed += page["jobs"]
            cursor = page["next_cursor"]
            if cursor is None:
                break
        ids = [j["id"] for j in listed]
        want = sorted(e["id"] for e in submissions.values())
        if len(ids) != len(set(ids)):
            failures.append(f"duplicate ids in the listing: {ids}")
        if sorted(ids) != want:
            failures.append(f"the listing has {len(ids)} jobs {sorted(ids)}, submitted {len(want)}: {want}")
        # A retry after all this still names the same job, and adds none.
        for name, entry in submissions.items():
            status, resp = api.json("POST", "/api/jobs", entry["body"], {"Idempotency-Key": entry["key"]})
            if status != 202 or resp["id"] != entry["id"]:
                failures.append(f"retrying POST {name}: {status}, job {resp.get('id')} (want {entry['id']})")
        if len(api.json("GET", "/api/jobs?limit=100")[1]["jobs"]) != len(want):
            failures.append("a retried POST added a job")

        # Each job: succeeded once, every pass, and the pixels of an uninterrupted render.
        refdir = os.path.join(tmp, "reference")
        os.makedirs(refdir)
        rows = []
        for name in order:
            entry = submissions[name]
            status, job = api.json("GET", f"/api/jobs/{entry['id']}")
            problems = []
            if job["state"] != "succeeded":
                problems.append(f"state {job['state']}: {job['error']}")
            stats = job.get("stats") or {}
            settings = job["settings"]
            if job["state"] == "succeeded":
                if stats.get("stop_reason") != "spp":
                    problems.append(f"stopped by {stats.get('stop_reason')}, not spp")
                if not (stats.get("passes") == job["passes_total"] == job["passes_done"] > 0):
                    problems.append(f"passes: stats {stats.get('passes')}, done {job['passes_done']}, "
                                    f"total {job['passes_total']}")
                passes = [p["pass"] for p in job["convergence"]]
                if passes != sorted(set(passes)) or (passes and passes[-1] != job["passes_total"]):
                    problems.append(f"convergence log passes {passes}")
                if settings["time_limit"] <= 0 or stats.get("render_seconds", 0) > settings["time_limit"] / 10:
                    problems.append(f"render took {stats.get('render_seconds')} s of a "
                                    f"{settings['time_limit']} s limit")
            verdict = "-"
            if job["state"] == "succeeded":
                got = os.path.join(refdir, f"{name}-server.exr")
                status, raw = api.request("GET", f"/api/jobs/{entry['id']}/image.exr")
                if status != 200:
                    problems.append(f"image.exr: {status}")
                else:
                    with open(got, "wb") as f:
                        f.write(raw)
                    scene_file = os.path.join(refdir, f"{name}.json")
                    with open(scene_file, "w") as f:
                        json.dump(scenes[name], f)
                    ref = os.path.join(refdir, f"{name}-cli.exr")
                    cmd = [binary, "render", scene_file, "-o", ref, "--quiet"]
                    for k, v in sorted(settings.items()):
                        cmd += ["--set", setting_arg(k, v)]
                    left = deadline - time.monotonic()
                    if left < 5:
                        raise TestFailure("out of time rendering the references")
                    try:
                        r = subprocess.run(cmd, capture_output=True, text=True, timeout=left)
                    except subprocess.TimeoutExpired:
                        raise TestFailure("out of time rendering the references")
                    if r.returncode != 0:
                        problems.append(f"reference render failed: {r.stderr.strip()}")
                    else:
                        same, detail = same_pixels(got, ref)
                        verdict = "identical" if same else "DIFFERENT"
                        if not same:
                            problems.append(f"image.exr differs from the CLI render: {detail}")
            rows.append((name, entry["id"][:8], job["state"], job["attempt"], job["passes_total"],
                         entry["posts"], verdict))
            failures += [f"{name} ({entry['id']}): {p}" for p in problems]

        failures += observer.problems
        log("")
        print("| job | id | state | attempts | passes | POSTs | image vs CLI |")
        print("|---|---|---|---:|---:|---:|---|")
        for row in rows:
            print("| " + " | ".join(str(c) for c in row) + " |")
        print(flush=True)
        interrupted = sum(1 for r in rows if r[3] > 1)
        leftovers = sum(1 for _, _, files in os.walk(data) for f in files if ".tmp" in f)
        log(f"{kills} kills ({kills_on_running} with a job running), {server.starts} server starts, "
            f"{interrupted}/{len(rows)} jobs rendered in more than one attempt, "
            f"{observer.pass_regressions} progress take-backs seen, "
            f"{leftovers} temporary files left in job folders")
        if leftovers:
            failures.append(f"{leftovers} temporary files left in job folders: a restarted server "
                            "removes those of killed writers, and nothing was killed since")
        if kills_on_running > 0 and interrupted == 0:
            failures.append("no job was ever interrupted: the kills missed every render")
        if failures:
            raise TestFailure("\n  ".join([f"{len(failures)} failure(s):"] + failures))
        ok = True
        log(f"PASS (seed {seed})")
    except TestFailure as e:
        log(f"FAIL (seed {seed}; rerun with CAUSTIC_CRASH_SEED={seed}): {e}")
        for n in range(max(1, server.starts - 1), server.starts + 1):
            tail = server.tail(n)
            if tail:
                log(f"server run {n} log:\n{tail}")
    finally:
        observer.stop.set()
        server.stop()
        if ok and not os.environ.get("CAUSTIC_CRASH_KEEP"):
            shutil.rmtree(tmp, ignore_errors=True)
        else:
            log(f"kept {tmp}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
