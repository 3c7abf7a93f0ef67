#!/usr/bin/env python3
"""Event delay of a scale-out (bench/README.md, "event_delay"): how long after a worker process
merges a task's passes into the PostgreSQL store a client following the job's Server-Sent Events
on the API process hears of it (LISTEN/NOTIFY, server/store/postgres/listener.h), beside the same
delay for one SQLite process (whose workers wake its event streams in memory).

The delay of an event is the time the client read it minus the time the pass was merged: the job's
started_at plus the last convergence point's seconds, both taken by the process that merged it on
this machine's clock (the commit, a few ms later, is inside the delay). Starts a throwaway
PostgreSQL (tests/support/postgres.sh), `caustic serve --store ... --workers 0` and one
`caustic worker --threads 1`; then a SQLite `caustic serve --threads 1`. Each renders --jobs jobs
of --passes passes in tasks of one pass, one job at a time. Prints p50, p90, p99 and max as a
Markdown table. Standard-library Python only; stops what it started.

usage: bench/event_delay.py [--binary PATH] [--jobs N] [--passes N]
"""

import argparse
import datetime
import http.client
import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = {
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40,
               "width": 64, "height": 64},
    "materials": {"white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
                  "lamp": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5],
                           "emission": [4, 4, 4]}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.8, "material": "white"},
               {"type": "sphere", "center": [0, 2, 1], "radius": 0.3, "material": "lamp"}],
}


def start(args, out_path, pattern, deadline=60):
    """Starts a process; waits for `pattern` on its stdout; returns (process, match)."""
    with open(out_path, "wb") as out:
        proc = subprocess.Popen(args, stdout=out, stderr=subprocess.DEVNULL,
                                start_new_session=True)
    end = time.monotonic() + deadline
    while time.monotonic() < end:
        with open(out_path, encoding="utf-8", errors="replace") as f:
            m = re.search(pattern, f.read())
        if m:
            return proc, m
        if proc.poll() is not None:
            break
        time.sleep(0.05)
    raise RuntimeError(f"{shlex.join(args[:2])} did not start")


def stop(proc):
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(timeout=30)


def epoch(iso):
    return datetime.datetime.fromisoformat(iso.replace("Z", "+00:00")).timestamp()


def delays(port, jobs, passes):
    """Renders `jobs` jobs one after the other; returns each progress event's delay (s)."""
    found = []
    for _ in range(jobs):
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
        body = {"scene": SCENE, "settings": {"spp": passes, "spp_per_pass": 1},
                "task_passes": 1}
        conn.request("POST", "/api/jobs", json.dumps(body), {"Content-Type": "application/json"})
        r = conn.getresponse()
        job = json.loads(r.read())
        assert r.status == 202, job
        conn.request("GET", f"/api/jobs/{job['id']}/events")
        stream = conn.getresponse()
        seen = 0
        event = None
        while True:
            line = stream.fp.readline().decode()
            if not line:
                break
            if line.startswith("event: "):
                event = line[7:].strip()
            elif line.startswith("data: "):
                received = time.time()
                data = json.loads(line[6:])
                points = data.get("convergence") or []
                if data.get("started_at") and points and data["passes_done"] > seen:
                    seen = data["passes_done"]
                    merged = epoch(data["started_at"]) + points[-1]["seconds"]
                    found.append(received - merged)
                if event == "end":
                    break
        conn.close()
    return found


def percentile(values, q):
    s = sorted(values)
    return s[min(len(s) - 1, int(q * len(s)))]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--binary", default=os.path.join(REPO, "build", "cli", "caustic"))
    p.add_argument("--jobs", type=int, default=5)
    p.add_argument("--passes", type=int, default=40)
    a = p.parse_args()
    tmp = tempfile.mkdtemp(prefix="caustic-event-delay-", dir="/tmp")
    # A folder of its own under /tmp: the cluster's user (postgres, as root) must get through.
    pg = tempfile.mkdtemp(prefix="caustic-event-delay-pg-", dir="/tmp")
    procs = []
    rows = []
    try:
        store = subprocess.run(["bash", os.path.join(REPO, "tests", "support", "postgres.sh"),
                                "start", pg, "--watch", str(os.getpid())], check=True,
                               capture_output=True, text=True).stdout.strip().splitlines()[-1]
        api, m = start([a.binary, "serve", "--port", "0", "--store", store, "--workers", "0"],
                       os.path.join(tmp, "api.out"), r"serving on http://127\.0\.0\.1:(\d+)/")
        procs.append(api)
        worker, _ = start([a.binary, "worker", "--store", store, "--threads", "1"],
                          os.path.join(tmp, "worker.out"), r"caustic: worker rendering")
        procs.append(worker)
        rows.append(("PostgreSQL: API process + 1 worker process",
                     delays(int(m.group(1)), a.jobs, a.passes)))
        for proc in procs:
            stop(proc)
        procs.clear()
        single, m = start([a.binary, "serve", "--port", "0", "--threads", "1", "--data",
                           os.path.join(tmp, "data")], os.path.join(tmp, "single.out"),
                          r"serving on http://127\.0\.0\.1:(\d+)/")
        procs.append(single)
        rows.append(("SQLite: one process", delays(int(m.group(1)), a.jobs, a.passes)))
    finally:
        for proc in procs:
            stop(proc)
        subprocess.run(["bash", os.path.join(REPO, "tests", "support", "postgres.sh"), "stop",
                        pg], capture_output=True)
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"`{shlex.join(sys.argv)}`, {time.strftime('%Y-%m-%d')}: delay from a merged pass to "
          "its Server-Sent Event on the API process, ms\n")
    print("| store | events | p50 | p90 | p99 | max |")
    print("|---|---|---|---|---|---|")
    for name, d in rows:
        ms = [1000 * x for x in d]
        print(f"| {name} | {len(ms)} | {percentile(ms, 0.5):.1f} | {percentile(ms, 0.9):.1f} | "
              f"{percentile(ms, 0.99):.1f} | {max(ms):.1f} |")


if __name__ == "__main__":
    main()
