"""Hostile requests against the real `caustic serve`: each gets its 4xx with an RFC 9457 problem
body (type/title/status/detail, and `pointer` = the JSON path where there is one), and after each
the server still answers /healthz.

Servers: `main` (default limits but a 1 MiB body limit, and an assets folder with links that lead
out of it), `token` (--token: POST and DELETE need it) and `queue` (--max-queued 1). Paths are sent
byte for byte over a socket where an HTTP client would normalize them ("/../", "%2e%2e", NUL)."""

import http.client
import json
import os
import shutil
import socket
import struct
import tempfile
import zlib

import pytest
import requests

from conftest import TINY_SCENE, assert_problem
from hostile_requests import (CASES, MAX_REQUEST_BYTES, NO_BODY, TOKEN, TRIANGLE_OBJ, UNKNOWN_ID,
                              scene_with, with_settings)


def grey_png(width, height):
    """A valid 8-bit grey PNG, written by hand (no imaging library needed)."""
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))
    rows = b"".join(b"\x00" + b"\x80" * width for _ in range(height))
    return (b"\x89PNG\r\n\x1a\n"
            + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


@pytest.fixture(scope="module")
def assets():
    """An assets folder with one good mesh and links that lead out of it."""
    root = tempfile.mkdtemp(prefix="caustic-assets-")
    inside = os.path.join(root, "assets")
    os.makedirs(os.path.join(inside, "sub"))
    with open(os.path.join(inside, "tiny.obj"), "w") as f:
        f.write(TRIANGLE_OBJ)
    with open(os.path.join(root, "outside.obj"), "w") as f:
        f.write(TRIANGLE_OBJ)
    os.symlink("/etc/passwd", os.path.join(inside, "passwd-link.obj"))
    os.symlink(os.path.join(root, "outside.obj"), os.path.join(inside, "outside-link.obj"))
    os.symlink("/etc", os.path.join(inside, "etc-link"))
    with open(os.path.join(inside, "grey.png"), "wb") as f:
        f.write(grey_png(4, 4))
    with open(os.path.join(inside, "broken.png"), "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n and then nothing a PNG holds")
    yield inside
    shutil.rmtree(root, ignore_errors=True)


@pytest.fixture(scope="module")
def servers(start_server, assets):
    made = {}

    def get(kind):
        if kind not in made:
            if kind == "main":
                made[kind] = start_server("--threads", "2", "--assets", assets,
                                          "--max-request-bytes", str(MAX_REQUEST_BYTES))
            elif kind == "token":
                made[kind] = start_server("--threads", "2", "--token", TOKEN)
            elif kind == "queue":
                made[kind] = start_server("--threads", "2", "--max-queued", "1")
        return made[kind]

    yield get
    for s in made.values():
        s.stop()


class RawResponse:
    """What assert_problem needs of a response read off a socket."""

    def __init__(self, status, headers, body):
        self.status_code, self.headers, self.content = status, headers, body
        self.text = body.decode("utf-8", "replace")

    def json(self):
        return json.loads(self.text)


def send_raw(server, data):
    with socket.create_connection(("127.0.0.1", server.port), timeout=30) as sock:
        sock.sendall(data)
        response = http.client.HTTPResponse(sock)
        response.begin()
        return RawResponse(response.status, response.headers, response.read())


def send(server, case):
    if case.raw is not None:
        return send_raw(server, case.raw)
    kw = {"headers": dict(case.headers)}
    if case.body is not NO_BODY:
        if isinstance(case.body, (str, bytes)) or hasattr(case.body, "__next__"):
            kw["data"] = case.body
            kw["headers"].setdefault("Content-Type", "application/json")
        else:
            kw["data"] = json.dumps(case.body)
            kw["headers"]["Content-Type"] = "application/json"
    try:
        return server.request(case.method, case.path, **kw)
    except requests.ConnectionError:
        if case.status != 413:
            raise
        # The server may answer 413 and close before it has read the whole body; the answer is
        # then lost to this client. Ask again without sending the body: Content-Length alone.
        data = kw.get("data")
        size = len(data) if isinstance(data, (str, bytes)) else MAX_REQUEST_BYTES + 1
        head = (f"POST {case.path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n"
                f"Content-Length: {size}\r\n\r\n").encode() + b"a" * size
        return send_raw(server, head)


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_hostile_request(servers, case):
    server = servers(case.server)
    r = send(server, case)
    body = assert_problem(r, case.status, case.pointer, case.detail)
    assert "root:" not in r.text  # nothing of /etc/passwd, ever
    if case.status == 401:
        assert r.headers.get("WWW-Authenticate") == "Bearer"
    # Nothing hostile was queued.
    assert body["status"] != 202
    server.healthy()


def test_no_hostile_request_made_a_job(servers):
    r = servers("main").get("/api/jobs", params={"limit": 100})
    assert r.status_code == 200 and r.json()["jobs"] == []


def test_mesh_inside_the_assets_folder_renders(servers):
    # The control for the mesh cases: a real file in the folder is fine.
    server = servers("main")
    r = server.submit({"scene": scene_with(shapes=[
        {"type": "mesh", "file": "tiny.obj", "material": "lamp"},
        {"type": "mesh", "file": "sub/../tiny.obj", "material": "white"}]),
        "settings": {"spp": 1}})
    # "sub/../tiny.obj" never leaves the folder, but ".." is refused outright.
    assert_problem(r, 422, "/scene/shapes/1/file", "..")
    r = server.submit({"scene": scene_with(shapes=[
        {"type": "mesh", "file": "tiny.obj", "material": "lamp"}]), "settings": {"spp": 1}})
    assert r.status_code == 202, r.text
    assert server.wait(r.json()["id"], {"succeeded", "failed"})["state"] == "succeeded"
    assert server.delete(f"/api/jobs/{r.json()['id']}").status_code == 204


def textured(texture):
    scene = scene_with()
    scene["shapes"].append({"type": "sphere", "center": [0, 0, 0], "radius": 0.5,
                            "material": "textured"})
    scene["materials"]["textured"] = {"type": "metallic_roughness",
                                      "base_color_texture": texture}
    return {"scene": scene, "settings": {"spp": 1}}


def test_bad_textures_are_422_at_their_path_and_a_good_one_renders(servers):
    server = servers("main")
    at = "/scene/materials/textured/base_color_texture"
    assert_problem(server.submit(textured("missing.png")), 422, at, "no file")
    assert_problem(server.submit(textured("broken.png")), 422, at, "broken.png")
    assert_problem(server.submit(textured({"file": "grey.png", "filter": "cubic"})), 422,
                   at + "/filter", "anisotropic")
    r = server.submit(textured({"file": "grey.png", "transform": {"scale": [4, 4]}}))
    assert r.status_code == 202, r.text
    job = server.wait(r.json()["id"], {"succeeded", "failed"})
    assert job["state"] == "succeeded", job
    assert server.delete(f"/api/jobs/{r.json()['id']}").status_code == 204


def test_invalid_utf8_idempotency_key_conflict(servers):
    # The 409 quotes the key: bytes that are not UTF-8 must not make it a 500.
    server = servers("main")
    key = b"key-\xff\xfe"
    first = server.submit({"scene": TINY_SCENE, "settings": {"spp": 1}},
                          headers={"Idempotency-Key": key})
    assert first.status_code == 202, first.text
    other = server.submit({"scene": TINY_SCENE, "settings": {"spp": 2}},
                          headers={"Idempotency-Key": key})
    assert_problem(other, 409, detail="key-")
    server.healthy()
    server.wait(first.json()["id"], {"succeeded"})
    assert server.delete(f"/api/jobs/{first.json()['id']}").status_code == 204


def test_token_server_reads_without_a_token_and_writes_with_it(servers):
    server = servers("token")
    assert server.get("/healthz").status_code == 200
    assert server.get("/api/jobs").status_code == 200
    assert server.get("/api/scenes").status_code == 200
    assert server.get("/metrics").status_code == 200
    body = {"scene": TINY_SCENE, "settings": {"spp": 1}}
    r = server.submit(body, headers={"Authorization": "Bearer " + TOKEN})
    assert r.status_code == 202, r.text
    job_id = r.json()["id"]
    assert server.get(f"/api/jobs/{job_id}").status_code == 200  # GET needs no token
    # The scheme is case-insensitive (RFC 9110, 11.1); the token is not.
    r = server.submit(body, headers={"Authorization": "bearer " + TOKEN})
    assert r.status_code == 202, r.text
    assert_problem(server.submit(body, headers={"Authorization": "Bearer " + TOKEN.upper()}), 401)
    server.wait(job_id, {"succeeded"})
    assert_problem(server.delete(f"/api/jobs/{job_id}"), 401)
    assert server.get(f"/api/jobs/{job_id}").status_code == 200  # still there
    assert server.delete(f"/api/jobs/{job_id}",
                         headers={"Authorization": "Bearer " + TOKEN}).status_code == 204


def test_full_queue_is_429_with_retry_after(servers):
    server = servers("queue")
    long_body = {"scene": "cornell-box",
                 "settings": {"spp": 4096, "spp_per_pass": 1, "time_limit": 120}}
    running = server.submit(long_body).json()["id"]
    server.wait(running, {"running"})
    queued = server.submit({"scene": TINY_SCENE, "settings": {"spp": 1}}).json()["id"]
    assert server.job(queued)["state"] == "queued"
    try:
        for i in range(3):
            r = server.submit({"scene": TINY_SCENE, "settings": {"spp": 1, "seed": i}})
            assert_problem(r, 429, detail="queue is full")
            assert int(r.headers["Retry-After"]) > 0
            server.healthy()
        # Once a place frees up, a submission is accepted again.
        assert server.post(f"/api/jobs/{queued}/cancel").status_code == 202
        r = server.submit({"scene": TINY_SCENE, "settings": {"spp": 1, "seed": 9}})
        assert r.status_code == 202, r.text
    finally:
        server.post(f"/api/jobs/{running}/cancel")
    server.wait(running, {"cancelled"})


def test_refused_body_does_not_spoil_the_connection(servers):
    # A 401 is sent before the body is read: it tells the client to close the connection, so that
    # the body left unread is not taken for the next request (a keep-alive client retries fine).
    server = servers("token")
    body = json.dumps({"scene": TINY_SCENE, "settings": {"spp": 1}})
    json_type = {"Content-Type": "application/json"}  # a body without one is 415
    with requests.Session() as session:
        for _ in range(3):
            r = session.post(server.url("/api/jobs"), data=body, timeout=30,
                             headers={"Authorization": "Bearer wrong", **json_type})
            assert_problem(r, 401)
            assert r.headers["Connection"] == "close"
        r = session.post(server.url("/api/jobs"), data=body, timeout=30,
                         headers={"Authorization": "Bearer " + TOKEN, **json_type})
        assert r.status_code == 202, r.text
    server.healthy()
    server.wait(r.json()["id"], {"succeeded"})


def test_post_without_a_body_needs_no_content_length(servers):
    # `curl -X POST .../cancel` (docs/http-api.md) sends neither Content-Length nor a body: it has none.
    server = servers("main")
    with socket.create_connection(("127.0.0.1", server.port), timeout=30) as sock:
        sock.settimeout(5)  # a server reading to the connection's close would answer 400 after 10 s
        sock.sendall(f"POST /api/jobs/{UNKNOWN_ID}/cancel HTTP/1.1\r\n"
                     "Host: 127.0.0.1\r\n\r\n".encode())
        response = http.client.HTTPResponse(sock)
        response.begin()
        r = RawResponse(response.status, response.headers, response.read())
    assert_problem(r, 404, detail="no job")


def test_photon_limit_applies_wherever_photons_are_traced(start_server):
    # --max-photons below the default photons (200000) must not refuse a path-traced job, which
    # traces none; a job that traces photons over it is refused, naming the setting: photon and
    # ppm, and path with either of its photon maps.
    server = start_server("--threads", "2", "--max-photons", "1000")
    r = server.submit({"scene": TINY_SCENE, "settings": {"spp": 1, "preset": "none"}})
    assert r.status_code == 202, r.text
    # auto's photon map, over the limit, is left out, and the job says why.
    r = server.submit({"scene": TINY_SCENE, "settings": {"spp": 1}})
    assert r.status_code == 202, r.text
    job = r.json()
    assert job["settings"]["indirect"] == "paths", job["preset_choice"]
    assert any("at most 1000 on this server" in reason for reason in job["preset_choice"]["reasons"])
    assert_problem(server.submit(with_settings(spp=1, caustics="photon_map")), 422,
                   "/settings/photons", "at most 1000")
    assert_problem(server.submit(with_settings(spp=1, indirect="photon_map", indirect_photons=5000)),
                   422, "/settings/indirect_photons", "at most 1000 on this server")
    r = server.submit(with_settings(spp=1, indirect="photon_map", indirect_photons=1000))
    assert r.status_code == 202, r.text
    for integrator in ("photon", "ppm"):
        assert_problem(server.submit(with_settings(integrator=integrator, spp=1)), 422,
                       "/settings/photons", "at most 1000")
        assert_problem(server.submit(with_settings(integrator=integrator, spp=1, photons=500,
                                                   caustic_photons=5000)), 422,
                       "/settings/caustic_photons")
    r = server.submit(with_settings(integrator="photon", spp=1, photons=500))
    assert r.status_code == 202, r.text
    server.wait(r.json()["id"], {"succeeded"})
    server.stop()
