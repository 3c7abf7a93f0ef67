#!/usr/bin/env python3
"""Admission latency of `caustic serve`: how long POST /api/jobs takes to answer, per scene and
integrator (bench/README.md, "admission_latency"). DESIGN.md: admission only validates and
estimates from counts, so its latency must not grow with the scene.

Starts the real server on 127.0.0.1 (a free port, a temporary data folder, a temporary assets
folder with copies of assets/meshes and a generated mesh of --triangles triangles, a temporary
scenes folder), then per scene and integrator submits --warmup jobs, then --jobs jobs one at a
time, timing each POST from sending it to reading its whole response. After each POST the job is
cancelled, awaited until it has ended (so that the worker never renders while a POST is timed) and
deleted. Prints the first POST of each case (cold caches) and the timed ones' p50, p99 and max as a
Markdown table. Standard-library Python only.

usage: bench/admission_latency.py [--binary PATH] [--jobs N] [--warmup N] [--triangles N]
                                  [--max-seconds S] [--smoke]
"""

import argparse
import http.client
import json
import math
import os
import re
import shlex
import shutil
import socket
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GRID_MESH = "grid.obj"
# The scenes' cameras are cut to this size in the temporary scenes folder: admission reads the
# resolution only to size the film, and the worker's render of each job is then short.
CAMERA_SIZE = 64


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--binary", default=os.path.join(REPO, "build", "cli", "caustic"))
    p.add_argument("--jobs", type=int, default=200, help="timed jobs per case (default 200)")
    p.add_argument("--warmup", type=int, default=20,
                   help="untimed jobs per case first (at least 1: the first is shown apart)")
    p.add_argument("--triangles", type=int, default=1000000, help="of the generated grid mesh")
    p.add_argument("--max-seconds", type=float, default=600,
                   help="a case stops early after this long (its row says how many jobs ran)")
    p.add_argument("--smoke", action="store_true",
                   help="2 jobs per case and a 20000-triangle grid: checks that it runs (CTest)")
    args = p.parse_args()
    args.warmup = max(1, args.warmup)
    if args.smoke:
        args.jobs, args.warmup, args.triangles = 2, 1, 20000
    return args


def write_grid(path, triangles):
    """A wavy height field of about `triangles` triangles (2 per grid cell) over the unit square,
    as an OBJ with one `v` line per vertex and one `f` triangle per line."""
    cols = max(1, int(math.sqrt(triangles / 2)))
    rows = max(1, triangles // (2 * cols))
    with open(path, "w") as f:
        for j in range(rows + 1):
            z = j / rows
            f.write("".join(
                f"v {i / cols:.6f} {0.02 * math.sin(40 * i / cols) * math.cos(40 * z):.6f} "
                f"{z:.6f}\n" for i in range(cols + 1)))
        for j in range(rows):
            lines = []
            for i in range(cols):
                a = j * (cols + 1) + i + 1  # OBJ indices start at 1
                b, c, d = a + 1, a + cols + 1, a + cols + 2
                lines.append(f"f {a} {c} {b}\nf {b} {c} {d}\n")
            f.write("".join(lines))
    return 2 * rows * cols


def make_folders(tmp, triangles):
    """The assets and scenes folders; returns {scene name: triangles}."""
    assets, scenes = os.path.join(tmp, "assets"), os.path.join(tmp, "scenes")
    os.makedirs(assets)
    os.makedirs(scenes)
    for name in os.listdir(os.path.join(REPO, "assets", "meshes")):
        shutil.copy(os.path.join(REPO, "assets", "meshes", name), assets)
    grid_triangles = write_grid(os.path.join(assets, GRID_MESH), triangles)

    def scene(name, source, mesh=None):
        with open(os.path.join(REPO, "scenes", source + ".json")) as f:
            doc = json.load(f)
        doc["camera"]["width"] = doc["camera"]["height"] = CAMERA_SIZE
        if mesh:  # the bunny's place, scaled into the box
            doc["shapes"][-1] = {"type": "mesh", "file": mesh, "material": "white",
                                 "transform": {"scale": 1.6, "translate": [-0.8, -0.95, -0.8]}}
        with open(os.path.join(scenes, name + ".json"), "w") as f:
            json.dump(doc, f, indent=1)

    scene("cornell-spheres", "cornell-spheres")
    scene("bunny", "bunny")
    scene("grid", "bunny", GRID_MESH)
    return assets, scenes, {"cornell-spheres": 0, "bunny": 69451, "grid": grid_triangles}


class Server:
    def __init__(self, binary, tmp, assets, scenes):
        self.log = open(os.path.join(tmp, "server.log"), "w+")
        env = {k: v for k, v in os.environ.items() if k not in ("CAUSTIC_TOKEN", "CAUSTIC_DATA")}
        # --max-queued: cancelled jobs never fill the queue anyway; --lease-seconds 2 makes the
        # worker see a cancellation within half a second (a heartbeat every quarter lease).
        self.proc = subprocess.Popen(
            [binary, "serve", "--host", "127.0.0.1", "--port", "0", "--data",
             os.path.join(tmp, "data"), "--assets", assets, "--scenes", scenes,
             "--max-queued", "1000000", "--lease-seconds", "2"],
            stdout=self.log, stderr=subprocess.STDOUT, env=env)
        deadline = time.monotonic() + 30
        while True:
            self.log.seek(0)
            m = re.search(r"serving on http://127\.0\.0\.1:(\d+)/", self.log.read())
            if m:
                break
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.log.seek(0)
                sys.exit("admission_latency: the server did not start:\n" + self.log.read())
            time.sleep(0.05)
        self.conn = http.client.HTTPConnection("127.0.0.1", int(m.group(1)), timeout=120)
        self.conn.connect()
        # Python sends a request's headers and body in one write; no Nagle delay on either side.
        self.conn.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

    def request(self, method, path, body=None):
        headers = {"Content-Type": "application/json"} if body is not None else {}
        self.conn.request(method, path, body=body, headers=headers)
        r = self.conn.getresponse()
        data = r.read()
        return r.status, data

    def stop(self):
        self.conn.close()
        self.proc.terminate()
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.log.close()


def one_job(server, body):
    """Submits one job and returns the POST's seconds; then cancels it, waits until it has ended
    and deletes it."""
    t0 = time.perf_counter()
    status, data = server.request("POST", "/api/jobs", body)
    seconds = time.perf_counter() - t0
    if status != 202:
        sys.exit(f"admission_latency: POST /api/jobs answered {status}: {data[:500]!r}")
    job = json.loads(data)["id"]
    server.request("POST", f"/api/jobs/{job}/cancel")
    deadline = time.monotonic() + 300
    while True:
        status, data = server.request("GET", f"/api/jobs/{job}")
        if status != 200 or json.loads(data)["state"] in ("succeeded", "failed", "cancelled"):
            break
        if time.monotonic() > deadline:
            sys.exit(f"admission_latency: job {job} did not end in 300 s")
        time.sleep(0.02)
    server.request("DELETE", f"/api/jobs/{job}")
    return seconds


def percentile(samples, q):
    """The q-th percentile (0-100) by linear interpolation between closest ranks."""
    s = sorted(samples)
    if len(s) == 1:
        return s[0]
    k = (len(s) - 1) * q / 100
    lo = math.floor(k)
    return s[lo] + (s[min(lo + 1, len(s) - 1)] - s[lo]) * (k - lo)


def main():
    args = parse_args()
    if not os.access(args.binary, os.X_OK):
        sys.exit(f"admission_latency: no caustic binary at {args.binary} (build it, or --binary)")
    command = " ".join(shlex.quote(a) for a in sys.argv)
    tmp = tempfile.mkdtemp(prefix="caustic-admission-")
    rows, server = [], None
    try:
        assets, scenes, triangles = make_folders(tmp, args.triangles)
        load_before = open("/proc/loadavg").read().split()[:3]
        server = Server(os.path.abspath(args.binary), tmp, assets, scenes)
        for name in ("cornell-spheres", "bunny", "grid"):
            for integrator in ("path", "photon"):
                body = json.dumps({"scene": name,
                                   "settings": {"integrator": integrator, "spp": 1}}).encode()
                # The first POST of a case meets cold caches (a mesh's counts, the page cache).
                first = one_job(server, body) * 1000
                for _ in range(args.warmup - 1):
                    one_job(server, body)
                samples, started = [], time.monotonic()
                while len(samples) < args.jobs and (
                        not samples or time.monotonic() - started < args.max_seconds):
                    samples.append(one_job(server, body) * 1000)
                p50, p99 = percentile(samples, 50), percentile(samples, 99)
                rows.append(f"| {name} | {triangles[name]} | {integrator} | {first:.2f} | "
                            f"{len(samples)} | {p50:.2f} | {p99:.2f} | {max(samples):.2f} |")
                print(f"admission_latency: {name}, {integrator}: p50 {p50:.2f} ms, p99 {p99:.2f} "
                      f"ms over {len(samples)} jobs", file=sys.stderr)
        load_after = open("/proc/loadavg").read().split()[:3]
    finally:
        if server:
            server.stop()
        shutil.rmtree(tmp, ignore_errors=True)
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                if l.startswith("model name")), "?")
    print(f"machine: nproc {os.cpu_count()}, {cpu}; load average {' '.join(load_before)} before, "
          f"{' '.join(load_after)} after")
    print(f"command: {command}")
    print(f"jobs: {args.warmup} warm-up then up to {args.jobs} timed per case (at most "
          f"{args.max_seconds:g} s), settings {{integrator, spp: 1}}, cameras {CAMERA_SIZE}²")
    print()
    print("| scene | mesh triangles | integrator | first ms | jobs | p50 ms | p99 ms | max ms |")
    print("|---|---:|---|---:|---:|---:|---:|---:|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
