"""Fixtures of the HTTP API tests (tests/server/test_*.py): the real `caustic serve` binary on
127.0.0.1, a free port (--port 0, read back from its first line of output) and a temporary data
folder, killed at teardown; helpers for problem+json bodies, Server-Sent Events and image files.

The binary: --caustic PATH, else $CAUSTIC_CLI, else build/cli/caustic (tests/server/run_pytest.sh
passes it). Every test has a time bound (pytest-timeout, pytest.ini) and every request a timeout.
"""

import json
import os
import re
import shutil
import signal
import struct
import subprocess
import tempfile
import time
import zlib

import pytest
import requests

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TIMEOUT = 30  # seconds, for any one request

# A scene small enough to render in milliseconds: one emitting sphere in front of a diffuse quad.
TINY_SCENE = {
    "camera": {
        "position": [0, 0, 3],
        "look_at": [0, 0, 0],
        "up": [0, 1, 0],
        "fov": 40,
        "width": 32,
        "height": 32,
    },
    "materials": {
        "white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
        "lamp": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5], "emission": [4, 4, 4]},
    },
    "shapes": [
        {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.3, "material": "lamp"},
        {
            "type": "quad",
            "origin": [-1, -1, -1],
            "u": [2, 0, 0],
            "v": [0, 2, 0],
            "material": "white",
        },
    ],
}

TITLES = {
    400: "Bad Request",
    401: "Unauthorized",
    403: "Forbidden",
    404: "Not Found",
    409: "Conflict",
    411: "Length Required",
    413: "Content Too Large",
    414: "URI Too Long",
    415: "Unsupported Media Type",
    422: "Unprocessable Content",
    429: "Too Many Requests",
    507: "Insufficient Storage",
}


def tiny_scene(**camera):
    """TINY_SCENE, a deep copy, with camera fields replaced."""
    scene = json.loads(json.dumps(TINY_SCENE))
    scene["camera"].update(camera)
    return scene


def pytest_addoption(parser):
    parser.addoption("--caustic", default=None, help="the caustic binary (default: $CAUSTIC_CLI "
                     "or build/cli/caustic)")


class Process:
    """A caustic process started in a session of its own, its messages in self.log_path."""

    proc = None
    log_path = None

    def log(self):
        try:
            with open(self.log_path, encoding="utf-8", errors="replace") as f:
                return f.read()[-4000:]
        except OSError:
            return ""

    def alive(self):
        return self.proc is not None and self.proc.poll() is None

    def terminate(self, timeout):
        """SIGTERM, then SIGKILL after `timeout` seconds."""
        if not self.alive():
            return
        os.killpg(self.proc.pid, signal.SIGTERM)
        try:
            self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait(timeout=timeout)


class Server(Process):
    """One `caustic serve` process."""

    def __init__(self, binary, workdir, args=(), env=None, verify=True):
        """`verify`: the CA file of a server started with --tls-cert (requests' `verify`)."""
        self.data = os.path.join(workdir, "data")
        self.log_path = os.path.join(workdir, "server.log")
        self.out_path = os.path.join(workdir, "server.out")
        self.args = [binary, "serve", "--host", "127.0.0.1", "--port", "0", "--data", self.data,
                     *args]
        self.env = env
        self.proc = None
        self.base = None
        self.verify = verify
        self.session = requests.Session()

    def start(self, deadline=30):
        with open(self.out_path, "wb") as out, open(self.log_path, "ab") as log:
            env = dict(os.environ)
            env.pop("CAUSTIC_TOKEN", None)
            env.pop("CAUSTIC_DATA", None)
            env.update(self.env or {})
            self.proc = subprocess.Popen(self.args, stdout=out, stderr=log, env=env,
                                         start_new_session=True)
        end = time.monotonic() + deadline
        pattern = re.compile(r"serving on (https?://127\.0\.0\.1:(\d+)/)")
        while True:
            with open(self.out_path, encoding="utf-8", errors="replace") as f:
                m = pattern.search(f.read())
            if m:
                self.base = m.group(1).rstrip("/")
                self.port = int(m.group(2))
                break
            if self.proc.poll() is not None:
                raise RuntimeError(f"caustic serve exited with {self.proc.returncode}:\n"
                                   + self.log())
            if time.monotonic() > end:
                raise RuntimeError("caustic serve printed no address in time:\n" + self.log())
            time.sleep(0.05)
        while True:
            try:
                r = requests.get(self.base + "/healthz", timeout=2, verify=self.verify)
                if r.status_code == 200:
                    return self
            except requests.RequestException:
                pass
            if self.proc.poll() is not None or time.monotonic() > end:
                raise RuntimeError("caustic serve never answered /healthz:\n" + self.log())
            time.sleep(0.05)

    def stop(self):
        self.session.close()
        self.terminate(15)

    # Requests, each with a timeout.
    def url(self, path):
        return self.base + path

    def request(self, method, path, **kw):
        kw.setdefault("timeout", TIMEOUT)
        # Per request: a session's `verify` gives way to $REQUESTS_CA_BUNDLE.
        kw.setdefault("verify", self.verify)
        return self.session.request(method, self.url(path), **kw)

    def get(self, path, **kw):
        return self.request("GET", path, **kw)

    def post(self, path, **kw):
        return self.request("POST", path, **kw)

    def delete(self, path, **kw):
        return self.request("DELETE", path, **kw)

    def submit(self, body, **kw):
        """POST /api/jobs with a JSON body (a dict) or raw bytes/str."""
        if isinstance(body, (bytes, str)):
            kw.setdefault("headers", {}).setdefault("Content-Type", "application/json")
            return self.post("/api/jobs", data=body, **kw)
        return self.post("/api/jobs", json=body, **kw)

    def job(self, job_id):
        r = self.get(f"/api/jobs/{job_id}")
        assert r.status_code == 200, r.text
        return r.json()

    def wait(self, job_id, states, deadline=60):
        """Polls a job until its state is one of `states`; returns it."""
        end = time.monotonic() + deadline
        while True:
            job = self.job(job_id)
            if job["state"] in states:
                return job
            assert time.monotonic() < end, f"job {job_id} still {job['state']}, not in {states}"
            time.sleep(0.05)

    def healthy(self):
        """The server still runs and answers /healthz."""
        assert self.alive(), "caustic serve died:\n" + self.log()
        r = requests.get(self.base + "/healthz", timeout=10)
        assert r.status_code == 200 and r.json() == {"status": "ok"}, r.text


@pytest.fixture(scope="session")
def caustic_bin(pytestconfig):
    path = (pytestconfig.getoption("--caustic") or os.environ.get("CAUSTIC_CLI")
            or os.path.join(ROOT, "build", "cli", "caustic"))
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        pytest.fail(f"no caustic binary at {path} (build it, or pass --caustic / $CAUSTIC_CLI)")
    return os.path.abspath(path)


@pytest.fixture(scope="session")
def start_server(caustic_bin):
    """A factory: start_server(*args, env=None) starts a server with more flags; every server it
    started is stopped (and its temporary folder removed) at the end of the session."""
    started = []

    def start(*args, env=None, verify=True):
        workdir = tempfile.mkdtemp(prefix="caustic-api-")
        server = Server(caustic_bin, workdir, args, env, verify)
        started.append((server, workdir))
        return server.start()

    yield start
    for server, workdir in started:
        server.stop()
        shutil.rmtree(workdir, ignore_errors=True)


@pytest.fixture(scope="module")
def server(start_server):
    """The server most tests share: default limits, one worker, two render threads."""
    s = start_server("--threads", "2")
    yield s
    s.stop()


# Checks.

def assert_problem(r, status, pointer=None, detail=None):
    """`r` is an RFC 9457 problem: the status, application/problem+json, type/title/status/detail,
    and `pointer` equal to the given JSON path (absent when None). `detail`, when given, is a
    substring the detail must contain."""
    assert r.status_code == status, f"expected {status}, got {r.status_code}: {r.text[:500]}"
    ctype = r.headers.get("Content-Type", "")
    assert ctype.split(";")[0].strip() == "application/problem+json", ctype
    body = r.json()
    assert isinstance(body.get("type"), str) and body["type"], body
    assert body.get("title") == TITLES[status], body
    assert body.get("status") == status, body
    assert isinstance(body.get("detail"), str) and body["detail"], body
    if pointer is None:
        assert "pointer" not in body, body
    else:
        assert body.get("pointer") == pointer, body
    if detail is not None:
        assert detail in body["detail"], body
    return body


def sse_events(server, job_id, deadline=60):
    """Reads GET /api/jobs/{id}/events to its end: a list of (event, data) with data decoded."""
    r = server.get(f"/api/jobs/{job_id}/events", stream=True, timeout=(10, deadline))
    assert r.status_code == 200, r.text
    assert r.headers["Content-Type"].startswith("text/event-stream")
    events, event, data = [], None, []
    end = time.monotonic() + deadline
    for line in r.iter_lines(decode_unicode=True):
        assert time.monotonic() < end, "the event stream did not end in time"
        if line == "":
            if event is not None or data:
                events.append((event, json.loads("\n".join(data)) if data else None))
            event, data = None, []
        elif line.startswith(":"):
            continue
        elif line.startswith("event:"):
            event = line[len("event:"):].strip()
        elif line.startswith("data:"):
            data.append(line[len("data:"):].strip())
    r.close()
    return events


def png_info(data):
    """Decodes a PNG fully (chunks, CRCs, zlib stream, scanline length): (width, height)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "no PNG signature"
    pos, idat, ihdr = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        chunk = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        assert zlib.crc32(kind + chunk) == crc, f"bad CRC in {kind}"
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", chunk)
        elif kind == b"IDAT":
            idat += chunk
        pos += 12 + length
        if kind == b"IEND":
            break
    assert ihdr is not None, "no IHDR"
    width, height, depth, color, _, _, interlace = ihdr
    channels = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[color]
    assert interlace == 0
    raw = zlib.decompress(idat)
    assert len(raw) == height * (1 + (width * channels * depth + 7) // 8), "wrong pixel data size"
    return width, height


def exr_info(data):
    """Reads an OpenEXR header: (width, height, channel names), checking the magic number and
    that the offset table fits the file."""
    assert data[:4] == b"\x76\x2f\x31\x01", "no OpenEXR magic number"
    pos, attrs = 8, {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        name = data[pos:name_end].decode()
        kind = data[name_end + 1:type_end].decode()
        (size,) = struct.unpack("<i", data[type_end + 1:type_end + 5])
        attrs[name] = (kind, data[type_end + 5:type_end + 5 + size])
        pos = type_end + 5 + size
    pos += 1
    x0, y0, x1, y1 = struct.unpack("<iiii", attrs["dataWindow"][1])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    channels, raw = [], attrs["channels"][1]
    i = 0
    while raw[i] != 0:
        end = raw.index(b"\0", i)
        channels.append(raw[i:end].decode())
        i = end + 1 + 16
    lines_per_block = {0: 1, 1: 1, 2: 1, 3: 16, 4: 32, 5: 16, 6: 32, 7: 256, 8: 256, 9: 256}
    compression = attrs["compression"][1][0]
    blocks = -(-height // lines_per_block[compression])
    offsets = struct.unpack(f"<{blocks}Q", data[pos:pos + 8 * blocks])
    assert all(pos + 8 * blocks <= o < len(data) for o in offsets), "offsets outside the file"
    return width, height, channels


# Jobs.

ID = re.compile(r"^[0-9a-f]{32}$")
UNKNOWN_ID = "0123456789abcdef0123456789abcdef"


def submit_ok(server, body, **kw):
    r = server.submit(body, **kw)
    assert r.status_code == 202, r.text
    job = r.json()
    assert ID.match(job["id"])
    assert r.headers["Location"] == f"/api/jobs/{job['id']}"
    assert job["links"]["self"] == r.headers["Location"]
    return job


def tiny_job(server, seed=0, spp=4):
    return submit_ok(server, {"scene": TINY_SCENE, "settings": {"spp": spp, "seed": seed}})


def run_to_end(server, job_id, deadline=60):
    events = sse_events(server, job_id, deadline)
    assert events, "no events"
    kind, last = events[-1]
    assert kind == "end", events
    assert all(k == "progress" for k, _ in events[:-1]), [k for k, _ in events]
    return last


@pytest.fixture
def long_job(server):
    """A job that renders for far longer than a test (the 512x512 Cornell box at 4096 spp, a
    fraction of a second a pass): the test sees it running; teardown cancels it and waits until it
    is no longer running."""
    job = submit_ok(server, {"scene": "cornell-box",
                             "settings": {"spp": 4096, "spp_per_pass": 1, "time_limit": 120}})
    server.wait(job["id"], {"running"}, deadline=60)
    yield job["id"]
    r = server.post(f"/api/jobs/{job['id']}/cancel")
    assert r.status_code in (202, 404), r.text
    if r.status_code == 202:
        server.wait(job["id"], {"cancelled", "succeeded", "failed"}, deadline=60)


# Scale-out (tests marked `scaleout`, run by CTest's scale_out_tests; tests/server/farm.py).

def pytest_configure(config):
    config.addinivalue_line("markers", "scaleout: needs PostgreSQL and worker processes")


@pytest.fixture(scope="module")
def postgres():
    """A PostgreSQL server for the module's tests."""
    from farm import PostgresCluster
    cluster = PostgresCluster()
    yield cluster
    cluster.stop()


@pytest.fixture
def farm(postgres, start_server, caustic_bin, tmp_path):
    """A factory of a scale-out on a fresh database: farm(workers=3, api_args=(), worker_args=())
    returns (api, [workers]): one `caustic serve --store ... --workers 0` and `workers` processes
    of `caustic worker --threads 1`; api.start_worker(*args, store=None, prefix=()) starts one more
    on the same store (or `store`: the same database by another way), through `prefix`. Every
    process is stopped at the end of the test."""
    from farm import Worker
    started = []

    def make(workers=3, api_args=(), worker_args=()):
        store = postgres.create_database()
        api = start_server("--store", store, "--workers", "0", *api_args)

        def start_worker(*args, store=store, prefix=()):
            worker = Worker(caustic_bin, store, str(tmp_path), "--threads", "1", *args,
                            prefix=prefix)
            started.append(worker)
            return worker.start()

        procs = [start_worker(*worker_args) for _ in range(workers)]
        api.store = store
        api.start_worker = start_worker
        return api, procs

    yield make
    for w in started:
        w.stop()
        # Shown only when the test failed (pytest's captured output of the teardown).
        print(f"--- {w.name} {' '.join(w.args[2:])}\n{w.log()}")
