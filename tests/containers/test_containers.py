"""The image of docker/Dockerfile and the topologies of docker/compose*.yaml, run for real with
podman (tests/containers/run.sh builds the images first; ../shared/containers.md).

1. One node: the image serves a job submitted over HTTP from outside with the token; its EXR has
   the pixels of the CLI's render of the same job in the same image; the job and its image outlive
   the container (a new one on the same volumes); the server runs as a user without privileges,
   refuses changes without the token, passes its health check, and serves HTTPS with a
   certificate this test makes.
2. Scale-out: compose.scale.yaml with podman-compose, PostgreSQL (a stand-in built from Debian's
   package under the official image's name, since no image can be pulled here), one API and two
   workers, renders a split job whose image is bit-identical to a single-process render.

Every container's port is published on loopback only; what a test made is removed at its end."""

import json
import os
import socket
import subprocess
import sys
import tempfile
import time

import pytest
import requests

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "server"))
from crash_test import same_pixels  # noqa: E402  (EXR bytes without dates, and idiff)

IMAGE = "caustic:latest"
TOKEN = "container-test-token"
PREFIX = "caustic-test-"
# The example bunny (a mesh from the assets volume), small enough for seconds on 2 cores.
SETTINGS = {"spp": 8, "spp_per_pass": 1, "seed": 5}
TIMEOUT = 30


def podman(*args, check=True, timeout=300, **kw):
    r = subprocess.run(["podman", *args], capture_output=True, text=True, timeout=timeout, **kw)
    if check and r.returncode != 0:
        raise AssertionError(f"podman {' '.join(args)} exited {r.returncode}:\n{r.stderr}")
    return r


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(what, check, deadline=120):
    end = time.monotonic() + deadline
    while True:
        try:
            value = check()
            if value:
                return value
        except requests.RequestException:
            pass
        assert time.monotonic() < end, f"timed out waiting for {what}"
        time.sleep(0.5)


def remove_leftovers():
    for c in podman("ps", "-a", "--format", "{{.Names}}").stdout.split():
        if c.startswith(PREFIX):
            podman("rm", "-f", "-t", "2", c, check=False)
    for v in podman("volume", "ls", "--format", "{{.Name}}").stdout.split():
        if v.startswith(PREFIX):
            podman("volume", "rm", "-f", v, check=False)


@pytest.fixture(scope="module")
def scratch():
    """A folder the containers' user (uid 10001) can write, for the CLI's images."""
    remove_leftovers()
    with tempfile.TemporaryDirectory(prefix=PREFIX) as folder:
        os.chmod(folder, 0o777)
        yield folder
    remove_leftovers()


def cli_render(scratch, name, scene="bunny", settings=SETTINGS):
    """The CLI's render of `scene` with `settings`, in the image; the EXR's path on this side."""
    flags = [f"--set={k}={json.dumps(v)}" for k, v in settings.items()]
    podman("run", "--rm", "-v", f"{scratch}:/out", IMAGE, "render", scene, *flags, "-q",
           "-o", f"/out/{name}.exr")
    return os.path.join(scratch, f"{name}.exr")


class Client:
    """Requests to a service published on loopback."""

    def __init__(self, port, scheme="http", verify=True):
        self.port, self.base, self.verify = port, f"{scheme}://127.0.0.1:{port}", verify

    def wait_until_healthy(self, deadline=120):
        wait_for(f"{self.base}/healthz", lambda: self.get("/healthz").status_code == 200, deadline)

    def get(self, path, **kw):
        return requests.get(self.base + path, timeout=TIMEOUT, verify=self.verify, **kw)

    def post(self, path, **kw):
        return requests.post(self.base + path, timeout=TIMEOUT, verify=self.verify, **kw)

    def render(self, body):
        """Submits `body` with the token; the finished job."""
        r = self.post("/api/jobs", json=body, headers={"Authorization": f"Bearer {TOKEN}"})
        assert r.status_code == 202, r.text
        job_id = r.json()["id"]
        return wait_for(f"job {job_id}", lambda: self.finished(job_id), deadline=600)

    def finished(self, job_id):
        job = self.get(f"/api/jobs/{job_id}").json()
        assert job["state"] not in ("failed", "cancelled"), job
        return job if job["state"] == "succeeded" else None

    def download(self, job, path):
        r = self.get(f"/api/jobs/{job['id']}/image.exr")
        assert r.status_code == 200, r.text
        with open(path, "wb") as f:
            f.write(r.content)
        return path


class Node(Client):
    """`caustic serve` in a container, its port published on loopback."""

    def __init__(self, name, volumes, *args, env=None, scheme="http", verify=True):
        super().__init__(free_port(), scheme, verify)
        self.name = PREFIX + name
        run = ["run", "-d", "--name", self.name, "-p", f"127.0.0.1:{self.port}:8080"]
        for k, v in (env or {"CAUSTIC_TOKEN": TOKEN}).items():
            run += ["-e", f"{k}={v}"]
        for v in volumes:
            run += ["-v", v]
        podman(*run, IMAGE, *args)
        self.wait_until_healthy()

    def remove(self):
        podman("rm", "-f", "-t", "5", self.name, check=False)


def test_one_node_serves_renders_persists_and_guards(scratch):
    volumes = [f"{PREFIX}data:/var/lib/caustic/data", f"{PREFIX}assets:/var/lib/caustic/assets"]
    node = Node("node", volumes)
    try:
        # A user without privileges runs the server.
        user = podman("exec", node.name, "id", "-u").stdout.strip()
        assert user != "0", user
        assert podman("top", node.name, "user").stdout.split()[1:] == ["caustic"]
        # Changes need the token; the health check passes.
        r = node.post("/api/jobs", json={"scene": "bunny"})
        assert r.status_code == 401 and r.headers["WWW-Authenticate"] == "Bearer", r.text
        assert podman("healthcheck", "run", node.name, check=False).returncode == 0
        # A job from outside, and the same job rendered by the CLI in the same image.
        job = node.render({"scene": "bunny", "settings": SETTINGS})
        served = node.download(job, os.path.join(scratch, "served.exr"))
        same, detail = same_pixels(served, cli_render(scratch, "cli"))
        assert same, detail
    finally:
        node.remove()
    # A new container on the same volumes finds the job and its image.
    node = Node("node-again", volumes)
    try:
        assert node.get(f"/api/jobs/{job['id']}").json()["state"] == "succeeded"
        again = node.download(job, os.path.join(scratch, "again.exr"))
        with open(again, "rb") as a, open(served, "rb") as b:
            assert a.read() == b.read()
    finally:
        node.remove()


def test_a_node_without_a_token_does_not_start():
    r = podman("run", "--rm", IMAGE, check=False, timeout=60)
    assert r.returncode != 0 and "--token" in r.stderr, r.stderr


def test_a_node_serves_https_with_a_token_from_a_file(scratch):
    secrets = os.path.join(scratch, "secrets")
    os.mkdir(secrets)
    cert, key = os.path.join(secrets, "cert.pem"), os.path.join(secrets, "key.pem")
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1",
                    "-subj", "/CN=127.0.0.1", "-addext", "subjectAltName=IP:127.0.0.1",
                    "-keyout", key, "-out", cert], check=True, capture_output=True, timeout=60)
    with open(os.path.join(secrets, "token"), "w") as f:
        f.write(TOKEN + "\n")
    for path in os.listdir(secrets):
        os.chmod(os.path.join(secrets, path), 0o644)  # the test's throwaway key, for uid 10001
    env = {"CAUSTIC_TOKEN_FILE": "/run/secrets/caustic/token",
           "CAUSTIC_TLS_CERT": "/run/secrets/caustic/cert.pem",
           "CAUSTIC_TLS_KEY": "/run/secrets/caustic/key.pem",
           "CAUSTIC_HEALTH_URL": "https://127.0.0.1:8080/healthz"}
    node = Node("tls", [f"{secrets}:/run/secrets/caustic:ro"], env=env, scheme="https",
                verify=cert)
    try:
        assert node.get("/healthz").json() == {"status": "ok"}
        with pytest.raises(requests.exceptions.ConnectionError):
            requests.get(f"http://127.0.0.1:{node.port}/healthz", timeout=TIMEOUT)
        assert node.post("/api/jobs", json={"scene": "bunny"}).status_code == 401
        assert podman("healthcheck", "run", node.name, check=False).returncode == 0
    finally:
        node.remove()


def compose(project, env, *args, timeout=600):
    r = subprocess.run(["podman-compose", "-p", project, "-f",
                        os.path.join(ROOT, "docker", "compose.scale.yaml"), *args],
                       capture_output=True, text=True, timeout=timeout, env={**os.environ, **env})
    assert r.returncode == 0, f"podman-compose {' '.join(args)}:\n{r.stdout}\n{r.stderr}"
    return r


def test_compose_scale_out_renders_a_split_job_bit_identical_to_one_process(scratch):
    project = PREFIX + "scale"
    api = Client(free_port())
    env = {"CAUSTIC_TOKEN": TOKEN, "POSTGRES_PASSWORD": "container-test-pw",
           "CAUSTIC_PORT": str(api.port), "CAUSTIC_WORKERS": "2"}
    try:
        compose(project, env, "up", "-d", "--no-build")
        api.wait_until_healthy(deadline=180)

        def two_workers():
            workers = api.get("/api/workers").json()["workers"]
            return workers if len(workers) == 2 else None

        workers = wait_for("two workers", two_workers)
        hosts = {w["host"] for w in workers}
        assert len(hosts) == 2, workers  # two containers
        job = api.render({"scene": "bunny", "settings": SETTINGS, "task_passes": 1})
        assert job["passes_done"] == 8 and job["stats"]["tasks"] == 8, job
        split = api.download(job, os.path.join(scratch, "split.exr"))
        same, detail = same_pixels(split, cli_render(scratch, "single"))
        assert same, detail
    finally:
        logs = subprocess.run(["podman", "logs", "--tail", "20", f"{project}_api_1"],
                              capture_output=True, text=True, timeout=60)
        print(logs.stdout, logs.stderr)
        compose(project, env, "down", "-v", "-t", "5")
        for n in podman("network", "ls", "--format", "{{.Name}}").stdout.split():
            if n.startswith(project):
                podman("network", "rm", "-f", n, check=False)
