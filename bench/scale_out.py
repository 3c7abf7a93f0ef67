#!/usr/bin/env python3
"""Scale-out speedup on PostgreSQL: the same split job rendered by 1, 2, 3, ... `caustic worker`
processes of one render thread each, beside one SQLite `caustic serve --threads 1` process
(bench/README.md, "Scale-out"; server/store/task.h).

Starts a throwaway PostgreSQL cluster (tests/support/postgres.sh, 127.0.0.1, fsync off), then per
worker count N (in --workers order, --repeats rounds): a fresh database, one API process
(`caustic serve --store ... --workers 0`) and N processes of `caustic worker --threads 1`; submits
the job (an example scene by name, path tracing, --spp in passes of --spp-per-pass, tasks of
--task-passes passes) and times it from the POST to the first GET that sees it succeeded (polled
every 20 ms). The reference is the job without task_passes on one SQLite `caustic serve --threads
1`. Prints one Markdown table: wall seconds, speedup over N = 1 and over the reference, the sum
of the tasks' render seconds and what is left of N x wall. Standard-library Python only.

A machine with C cores cannot run more than C workers of one thread at once: on 2 cores, N = 3
cannot beat N = 2.

usage: bench/scale_out.py [--binary PATH] [--workers 1,2,3] [--scene NAME] [--spp N]
                          [--spp-per-pass N] [--task-passes N] [--repeats N] [--smoke]
"""

import argparse
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
import urllib.request
import uuid

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
POSTGRES_SH = os.path.join(REPO, "tests", "support", "postgres.sh")


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--binary", default=os.path.join(REPO, "build", "cli", "caustic"))
    p.add_argument("--workers", default="1,2,3", help="worker process counts (default 1,2,3)")
    p.add_argument("--scene", default="cornell-box", help="an example scene, by name")
    p.add_argument("--spp", type=int, default=48)
    p.add_argument("--spp-per-pass", type=int, default=1)
    p.add_argument("--task-passes", type=int, default=8, help="passes per task (serve's default)")
    p.add_argument("--repeats", type=int, default=1,
                   help="rounds of every configuration, interleaved (medians are reported)")
    p.add_argument("--smoke", action="store_true",
                   help="4 spp, workers 1,2: checks that it runs (CTest)")
    args = p.parse_args()
    args.workers = [int(n) for n in args.workers.split(",")]
    if args.smoke:
        args.spp, args.spp_per_pass, args.task_passes, args.workers = 4, 1, 2, [1, 2]
    return args


class Process:
    """A caustic process in its own session, its output in `folder`; `ready` is the pattern of
    the stdout line it prints once it serves."""

    def __init__(self, args, folder, name, ready):
        self.out_path = os.path.join(folder, name + ".out")
        self.log_path = os.path.join(folder, name + ".log")
        env = {k: v for k, v in os.environ.items() if k not in ("CAUSTIC_TOKEN", "CAUSTIC_DATA",
                                                                 "CAUSTIC_STORE")}
        with open(self.out_path, "wb") as out, open(self.log_path, "wb") as log:
            self.proc = subprocess.Popen(args, stdout=out, stderr=log, env=env,
                                         start_new_session=True)
        deadline = time.monotonic() + 60
        while True:
            with open(self.out_path, encoding="utf-8", errors="replace") as f:
                self.match = re.search(ready, f.read())
            if self.match:
                return
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.stop()
                with open(self.log_path, encoding="utf-8", errors="replace") as f:
                    sys.exit(f"scale_out: {' '.join(args[:2])} did not start:\n{f.read()[-3000:]}")
            time.sleep(0.05)

    def stop(self):
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGTERM)
            try:
                self.proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()


def serve(binary, folder, *args):
    """A `caustic serve` on a free port; returns (process, base URL)."""
    name = "serve-" + uuid.uuid4().hex[:6]
    p = Process([binary, "serve", "--host", "127.0.0.1", "--port", "0", "--data",
                 os.path.join(folder, name), *args], folder, name,
                r"serving on (http://127\.0\.0\.1:\d+)/")
    return p, p.match.group(1)


def call(base, method, path, body=None):
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(base + path, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=60) as r:
        return json.loads(r.read())


def render(base, body):
    """Submits `body`; returns (wall seconds from the POST until it is seen succeeded, job)."""
    start = time.perf_counter()
    job = call(base, "POST", "/api/jobs", body)
    while True:
        job = call(base, "GET", f"/api/jobs/{job['id']}")
        if job["state"] in ("succeeded", "failed", "cancelled"):
            break
        time.sleep(0.02)
    wall = time.perf_counter() - start
    if job["state"] != "succeeded":
        sys.exit(f"scale_out: the job {job['state']}: {job.get('error')}")
    return wall, job


class Cluster:
    def __init__(self):
        # Its own folder under /tmp: the cluster's user (postgres, when run as root) must get
        # through its parents.
        self.folder = folder = tempfile.mkdtemp(prefix="caustic-scale-out-pg-", dir="/tmp")
        out = subprocess.run(["bash", POSTGRES_SH, "start", folder, "--watch", str(os.getpid())],
                             capture_output=True, text=True, timeout=120)
        if out.returncode != 0:
            sys.exit("scale_out: postgres.sh start failed:\n" + out.stdout + out.stderr)
        self.url = out.stdout.strip().splitlines()[-1]
        self.databases = 0

    def create_database(self):
        self.databases += 1
        name = f"scale_out_{self.databases}"
        subprocess.run(["psql", self.url, "-v", "ON_ERROR_STOP=1", "-qAtc",
                        f"CREATE DATABASE {name}"], check=True, capture_output=True, timeout=60)
        return self.url.rsplit("/", 1)[0] + "/" + name

    def stop(self):
        subprocess.run(["bash", POSTGRES_SH, "stop", self.folder], capture_output=True,
                       timeout=120)

    def cpu_seconds(self):
        """CPU seconds the server's processes have used: the postmaster's own and those of its
        children it has reaped (cutime, cstime), and its live children's."""
        with open(os.path.join(self.folder, "data", "postmaster.pid")) as f:
            postmaster = int(f.readline())
        tick = os.sysconf("SC_CLK_TCK")
        total = 0
        for pid in os.listdir("/proc"):
            if not pid.isdigit():
                continue
            try:
                with open(f"/proc/{pid}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            ppid, utime, stime, cutime, cstime = (int(fields[i]) for i in (1, 11, 12, 13, 14))
            if int(pid) == postmaster:
                total += utime + stime + cutime + cstime
            elif ppid == postmaster:
                total += utime + stime
        return total / tick


def run_farm(binary, cluster, folder, workers, body):
    """One render of `body` by `workers` worker processes on a fresh database."""
    store = cluster.create_database()
    procs = []
    try:
        api, base = serve(binary, folder, "--store", store, "--workers", "0")
        procs.append(api)
        for i in range(workers):
            procs.append(Process([binary, "worker", "--store", store, "--threads", "1"], folder,
                                 f"worker-{workers}-{i}-{uuid.uuid4().hex[:4]}",
                                 r"caustic: worker rendering"))
        cpu = cluster.cpu_seconds()
        wall, job = render(base, body)
        job["database_cpu_seconds"] = cluster.cpu_seconds() - cpu
        return wall, job
    finally:
        for p in reversed(procs):
            p.stop()


def run_single(binary, folder, body):
    """One render of `body` by one SQLite process with one render thread."""
    proc, base = serve(binary, folder, "--threads", "1")
    try:
        return render(base, body)
    finally:
        proc.stop()


def median(values):
    s = sorted(values)
    n = len(s)
    return s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])


def main():
    args = parse_args()
    if not os.access(args.binary, os.X_OK):
        sys.exit(f"scale_out: no caustic binary at {args.binary} (build it, or --binary)")
    binary = os.path.abspath(args.binary)
    pg_bin = os.environ.get("CAUSTIC_PG_BIN", "/usr/lib/postgresql/15/bin")
    if not os.access(os.path.join(pg_bin, "initdb"), os.X_OK):
        print(f"scale_out: no PostgreSQL server binaries in {pg_bin}: skipped", file=sys.stderr)
        sys.exit(77)
    command = " ".join(shlex.quote(a) for a in sys.argv)
    settings = {"integrator": "path", "spp": args.spp, "spp_per_pass": args.spp_per_pass}
    single_body = {"scene": args.scene, "settings": settings}
    farm_body = {**single_body, "task_passes": args.task_passes}
    folder = tempfile.mkdtemp(prefix="caustic-scale-out-", dir="/tmp")
    cluster = None
    results = {}  # "single" or N -> [(wall, job)]
    try:
        load_before = open("/proc/loadavg").read().split()[:3]
        cluster = Cluster()
        for _ in range(args.repeats):
            results.setdefault("single", []).append(run_single(binary, folder, single_body))
            print(f"scale_out: single process {results['single'][-1][0]:.2f} s", file=sys.stderr)
            for n in args.workers:
                results.setdefault(n, []).append(
                    run_farm(binary, cluster, folder, n, farm_body))
                print(f"scale_out: {n} worker(s) {results[n][-1][0]:.2f} s", file=sys.stderr)
        load_after = open("/proc/loadavg").read().split()[:3]
    finally:
        if cluster:
            cluster.stop()
        shutil.rmtree(folder, ignore_errors=True)
    print_report(args, command, load_before, load_after, results)


def print_report(args, command, load_before, load_after, results):
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                if l.startswith("model name")), "?")
    cores = len(os.sched_getaffinity(0))
    passes = -(-args.spp // args.spp_per_pass)
    tasks = -(-passes // args.task_passes)
    print(f"machine: nproc {cores}, {cpu}; load average {' '.join(load_before)} before, "
          f"{' '.join(load_after)} after")
    print(f"command: {command}")
    print(f"job: {args.scene} (by name), path, {args.spp} spp in {passes} passes of "
          f"{args.spp_per_pass} spp; split: {tasks} tasks of {args.task_passes} passes; "
          f"{args.repeats} round(s), medians")
    print(f"note: this machine has {cores} cores: more than {cores} single-thread workers "
          f"cannot render faster than {cores}, they only share the cores.")
    print()
    print("| renderer | wall s | speedup over 1 worker | speedup over one process | "
          "render s (sum) | render s per pass | N x wall - render s | database CPU s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    single = median([w for w, _ in results["single"]])
    one = median([w for w, _ in results[args.workers[0]]]) if args.workers else single
    for key in ["single"] + args.workers:
        wall = median([w for w, _ in results[key]])
        render_s = median([j["stats"]["render_seconds"] for _, j in results[key]])
        n = 1 if key == "single" else key
        name = ("one SQLite process, --threads 1" if key == "single"
                else f"{key} worker process(es), --threads 1")
        speedup = "" if key == "single" else f"{one / wall:.2f}"
        db = ("" if key == "single" else
              f"{median([j['database_cpu_seconds'] for _, j in results[key]]):.2f}")
        print(f"| {name} | {wall:.2f} | {speedup} | {single / wall:.2f} | {render_s:.2f} | "
              f"{render_s / passes:.3f} | {n * wall - render_s:.2f} | {db} |")


if __name__ == "__main__":
    main()
