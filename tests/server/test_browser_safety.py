"""The rules against other web sites (docs/security.md), against the real `caustic serve`: a page
on any site the user visits can make the browser send requests to 127.0.0.1, "simple" requests
(a text/plain body, a form) need no preflight, and DNS rebinding makes a foreign name resolve to
127.0.0.1. Each refusal is checked by its status and problem detail, and by what it did not do
(no job made, none cancelled or deleted). Also: --allow-origin (CORS for a front end of one's
own), and the access log, one line per request."""

import http.client
import json
import re
import socket
import time

import pytest

from conftest import TINY_SCENE, UNKNOWN_ID, assert_problem, run_to_end, submit_ok

JOB = {"scene": TINY_SCENE, "settings": {"spp": 1}}
EVIL = "http://evil.example"
FRONT_END = "http://localhost:5173"  # a development server of one's own, on another port


def job_ids(server):
    r = server.get("/api/jobs", params={"limit": 100})
    assert r.status_code == 200, r.text
    return {j["id"] for j in r.json()["jobs"]}


@pytest.fixture
def no_new_job(server):
    """Fails the test if it made a job."""
    before = job_ids(server)
    yield
    assert job_ids(server) == before


# Media types: a body is the type its route takes.

@pytest.mark.parametrize("content_type", ["text/plain", "text/plain;charset=UTF-8",
                                          "application/x-www-form-urlencoded",
                                          "multipart/form-data; boundary=x", "application/jsonx",
                                          "application/json-seq", "json"])
def test_post_of_another_media_type_is_415(server, no_new_job, content_type):
    # What a page on another site can send without a preflight (fetch with mode "no-cors", a
    # form): the body is valid JSON, only its declared type is wrong.
    r = server.post("/api/jobs", data=json.dumps(JOB), headers={"Content-Type": content_type})
    assert_problem(r, 415, detail=f'POST /api/jobs takes application/json, not "{content_type}"')
    assert r.headers["Connection"] == "close"  # refused before the body was read


def test_form_posts_are_415(server, no_new_job):
    # requests encodes these as a browser's form would.
    r = server.post("/api/jobs", data={"scene": "cornell-box"})
    assert r.request.headers["Content-Type"] == "application/x-www-form-urlencoded"
    assert_problem(r, 415, detail="not \"application/x-www-form-urlencoded\"")
    r = server.post("/api/jobs", files={"scene": ("scene.json", json.dumps(JOB))})
    assert r.request.headers["Content-Type"].startswith("multipart/form-data; boundary=")
    assert_problem(r, 415, detail="not \"multipart/form-data")


def test_body_without_a_content_type_is_415(server, no_new_job):
    r = server.post("/api/jobs", data=json.dumps(JOB).encode())
    assert "Content-Type" not in r.request.headers
    assert_problem(r, 415, detail="POST /api/jobs needs a Content-Type: it takes application/json")


@pytest.mark.parametrize("content_type", ["application/json", "Application/JSON",
                                          "application/json; charset=utf-8",
                                          "application/json ;charset=UTF-8"])
def test_json_is_accepted_with_parameters_and_in_any_case(server, content_type):
    r = server.post("/api/jobs", data=json.dumps(JOB), headers={"Content-Type": content_type})
    assert r.status_code == 202, r.text


def test_body_on_cancel_and_delete_is_415(server, long_job):
    for method, path in (("POST", f"/api/jobs/{long_job}/cancel"),
                         ("DELETE", f"/api/jobs/{long_job}")):
        for headers in ({"Content-Type": "application/x-www-form-urlencoded"},
                        {"Content-Type": "application/json"}, {}):
            r = server.request(method, path, data="x=1", headers=headers)
            assert_problem(r, 415, detail=f"{method} /api/jobs/{long_job}")
            assert "takes no body" in r.json()["detail"]
    job = server.job(long_job)
    assert job["state"] == "running" and job["cancel_requested"] is False


# Origin: a state change from another site's page is refused.

@pytest.mark.parametrize("origin", [EVIL, "null", "http://127.0.0.1", "https://127.0.0.1:{port}",
                                    "http://localhost:{port}", "http://127.0.0.1:{port}.evil"])
def test_cross_origin_submit_is_403(server, no_new_job, origin):
    origin = origin.format(port=server.port)
    r = server.post("/api/jobs", json=JOB, headers={"Origin": origin})
    assert_problem(r, 403, detail=f'POST from the origin "{origin}" is refused')
    assert "Access-Control-Allow-Origin" not in r.headers


def test_cross_origin_cancel_and_delete_are_403(server, long_job):
    r = server.post(f"/api/jobs/{long_job}/cancel", headers={"Origin": EVIL})
    assert_problem(r, 403, detail=f'POST from the origin "{EVIL}"')
    r = server.delete(f"/api/jobs/{long_job}", headers={"Origin": EVIL})
    assert_problem(r, 403, detail=f'DELETE from the origin "{EVIL}"')
    r = server.delete(f"/api/jobs/{long_job}", headers={"Origin": "null"})
    assert_problem(r, 403, detail='DELETE from the origin "null"')
    # Neither cancelled nor deleted.
    job = server.job(long_job)
    assert job["state"] == "running" and job["cancel_requested"] is False


def test_an_empty_form_cannot_cancel(server, long_job):
    # A fieldless form another site posts has no body but a form's type (and, from an old
    # browser, no Origin): refused by its type alone.
    for content_type in ("application/x-www-form-urlencoded", "multipart/form-data",
                         "text/plain"):
        r = server.post(f"/api/jobs/{long_job}/cancel", headers={"Content-Type": content_type})
        assert_problem(r, 415, detail=f"is not taken from a form or as {content_type}")
    job = server.job(long_job)
    assert job["state"] == "running" and job["cancel_requested"] is False


TRIANGLE_OBJ = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"


def test_other_sites_cannot_upload_or_delete_assets(server):
    obj = {"Content-Type": "model/obj"}
    r = server.post("/api/assets", data=TRIANGLE_OBJ, headers={**obj, "Origin": EVIL})
    assert_problem(r, 403, detail=f'POST from the origin "{EVIL}"')
    r = server.post("/api/assets", data=TRIANGLE_OBJ,
                    headers={**obj, "Host": f"evil.example:{server.port}"})
    assert_problem(r, 403, detail='the Host "evil.example')
    assert server.get("/api/assets").json()["assets"] == []
    asset = server.post("/api/assets", data=TRIANGLE_OBJ, headers=obj).json()
    r = server.delete(f"/api/assets/{asset['id']}", headers={"Origin": EVIL})
    assert_problem(r, 403, detail=f'DELETE from the origin "{EVIL}"')
    r = server.delete(f"/api/assets/{asset['id']}", headers={"Host": "evil.example"})
    assert_problem(r, 403, detail='the Host "evil.example"')
    assert server.get(f"/api/assets/{asset['id']}").status_code == 200


def test_own_origin_and_no_origin_are_accepted(server):
    # The page served by this server (its origin is the Host it asked) and curl, which sends none.
    own = submit_ok(server, JOB, headers={"Origin": server.base})
    plain = submit_ok(server, JOB)
    for job in (own, plain):
        server.wait(job["id"], {"succeeded"})
    r = server.delete(f"/api/jobs/{own['id']}", headers={"Origin": server.base})
    assert r.status_code == 204, r.text
    assert server.delete(f"/api/jobs/{plain['id']}").status_code == 204


def test_reads_need_no_origin_check(server):
    # A GET changes nothing; the browser keeps another site from reading the answer (no CORS).
    r = server.get("/api/jobs", headers={"Origin": EVIL})
    assert r.status_code == 200 and "Access-Control-Allow-Origin" not in r.headers


# Host: while bound to loopback, only loopback names (DNS rebinding).

@pytest.mark.parametrize("host", ["evil.example:{port}", "evil.example", "localhost.evil.example",
                                  "foo.localhost:{port}", "127.0.0.1.nip.io:{port}", "[::2]:{port}",
                                  "0x7f.0.0.1:{port}", "127.1:{port}", "localhost:{port}:1",
                                  "localhost:port", "[::1", "10.0.0.1:{port}"])
def test_foreign_host_is_403(server, no_new_job, host):
    host = host.format(port=server.port)
    for method, path, kw in (("GET", "/api/jobs", {}), ("GET", "/", {}),
                             ("GET", "/healthz", {}), ("POST", "/api/jobs", {"json": JOB})):
        r = server.request(method, path, headers={"Host": host}, **kw)
        assert_problem(r, 403, detail=f'the Host "{host}" is not this machine\'s loopback')


@pytest.mark.parametrize("host", ["127.0.0.1:{port}", "127.0.0.1", "localhost:{port}",
                                  "LocalHost:{port}", "localhost", "127.8.9.10:{port}",
                                  "[::1]:{port}", "[::1]", "[0:0:0:0:0:0:0:1]:{port}"])
def test_loopback_hosts_are_accepted(server, host):
    host = host.format(port=server.port)
    r = server.get("/healthz", headers={"Host": host})
    assert r.status_code == 200, r.text
    # Its own page's origin is that Host: a submission from it is accepted.
    r = server.post("/api/jobs", json=JOB, headers={"Host": host, "Origin": "http://" + host})
    assert r.status_code == 202, r.text


def raw_request(server, text):
    with socket.create_connection(("127.0.0.1", server.port), timeout=30) as sock:
        sock.sendall(text.encode())
        response = http.client.HTTPResponse(sock)
        response.begin()
        return response.status, response.read()


def test_request_without_host(server):
    # HTTP/1.1 requires Host (RFC 9112, section 3.2); HTTP/1.0 has none, and no browser sends it.
    for host in ("", "Host:\r\n", "Host: \r\n"):  # cpp-httplib drops a header with no value
        status, body = raw_request(server, f"GET /healthz HTTP/1.1\r\n{host}Connection: close\r\n\r\n")
        assert status == 400 and "needs a Host header" in json.loads(body)["detail"]
    status, body = raw_request(server, "GET /healthz HTTP/1.0\r\n\r\n")
    assert status == 200 and json.loads(body) == {"status": "ok"}
    # Without Host there is no own origin: a change from a page is refused.
    status, body = raw_request(server, f"POST /api/jobs/{UNKNOWN_ID}/cancel HTTP/1.0\r\n"
                                       f"Origin: {server.base}\r\n\r\n")
    assert status == 403, body


# --allow-origin: a front end of one's own on another origin.

@pytest.fixture(scope="module")
def cors_server(start_server):
    s = start_server("--threads", "2", "--allow-origin", FRONT_END,
                     "--allow-origin", "https://render.example.org")
    yield s
    s.stop()


def test_allowed_origin_changes_jobs_and_reads_answers(cors_server):
    r = cors_server.post("/api/jobs", json=JOB, headers={"Origin": FRONT_END})
    assert r.status_code == 202, r.text
    assert r.headers["Access-Control-Allow-Origin"] == FRONT_END
    assert "Location" in r.headers["Access-Control-Expose-Headers"]
    assert "Origin" in r.headers["Vary"]
    job_id = r.json()["id"]
    r = cors_server.get(f"/api/jobs/{job_id}", headers={"Origin": FRONT_END})
    assert r.status_code == 200 and r.headers["Access-Control-Allow-Origin"] == FRONT_END
    # A refusal is readable too, so that the front end can show it.
    r = cors_server.post("/api/jobs", data="{}", headers={"Origin": FRONT_END,
                                                         "Content-Type": "text/plain"})
    assert_problem(r, 415, detail="takes application/json")
    assert r.headers["Access-Control-Allow-Origin"] == FRONT_END
    cors_server.wait(job_id, {"succeeded"})
    r = cors_server.delete(f"/api/jobs/{job_id}", headers={"Origin": "https://render.example.org"})
    assert r.status_code == 204, r.text
    assert r.headers["Access-Control-Allow-Origin"] == "https://render.example.org"


def test_other_origins_stay_refused_with_allowed_ones(cors_server):
    before = job_ids(cors_server)
    for origin in (EVIL, FRONT_END + "/", "http://localhost:5174", "http://localhost", "null",
                   "https://localhost:5173"):
        r = cors_server.post("/api/jobs", json=JOB, headers={"Origin": origin})
        assert_problem(r, 403, detail=f'POST from the origin "{origin}"')
        assert "Access-Control-Allow-Origin" not in r.headers
        r = cors_server.get("/api/jobs", headers={"Origin": origin})
        assert r.status_code == 200 and "Access-Control-Allow-Origin" not in r.headers
    assert job_ids(cors_server) == before


def test_preflight(cors_server):
    preflight = {"Access-Control-Request-Method": "POST",
                 "Access-Control-Request-Headers": "content-type,idempotency-key"}
    r = cors_server.request("OPTIONS", "/api/jobs", headers={"Origin": FRONT_END, **preflight})
    assert r.status_code == 204, r.text
    assert r.headers["Access-Control-Allow-Origin"] == FRONT_END  # never "*"
    assert set(r.headers["Access-Control-Allow-Methods"].split(", ")) == {"GET", "POST", "DELETE"}
    assert {"content-type", "idempotency-key", "authorization"} <= {
        h.strip().lower() for h in r.headers["Access-Control-Allow-Headers"].split(",")}
    r = cors_server.request("OPTIONS", f"/api/jobs/{UNKNOWN_ID}", headers={
        "Origin": FRONT_END, "Access-Control-Request-Method": "DELETE"})
    assert r.status_code == 204 and r.headers["Access-Control-Allow-Origin"] == FRONT_END
    r = cors_server.request("OPTIONS", "/api/jobs", headers={"Origin": EVIL, **preflight})
    assert_problem(r, 403, detail=f'the origin "{EVIL}" may not call this API')
    assert "Access-Control-Allow-Origin" not in r.headers


def test_a_server_without_allowed_origins_refuses_every_preflight(server):
    r = server.request("OPTIONS", "/api/jobs", headers={
        "Origin": FRONT_END, "Access-Control-Request-Method": "POST"})
    assert_problem(r, 403, detail="may not call this API")


# The access log.

ACCESS_LINE = re.compile(r"^\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\.\d{3} access (?P<peer>\S+) "
                         r"(?P<method>\S+) (?P<path>\S+) (?P<status>\d{3}) (?P<bytes>\d+|-) "
                         r"(?P<ms>\d+\.\d|-) ms$")


def access_lines(text):
    return [m.groupdict() for m in map(ACCESS_LINE.match, text.splitlines()) if m]


def logged(read, count, deadline=10):
    """The access lines of read() once there are at least `count` (a line is written after its
    response has been sent, so it may come a moment after the client has it)."""
    end = time.monotonic() + deadline
    while len(lines := access_lines(read())) < count and time.monotonic() < end:
        time.sleep(0.05)
    return lines


def settled(read, quiet=0.5):
    """How many access lines read() has once no new one has come for `quiet` seconds."""
    count = len(logged(read, 1))
    while True:
        time.sleep(quiet)
        if (now := len(access_lines(read()))) == count:
            return count
        count = now


def test_access_log_has_a_line_per_request(start_server, tmp_path):
    log = tmp_path / "access.log"
    server = start_server("--threads", "2", "--access-log", str(log))
    plain = {"Accept-Encoding": "identity"}  # the bytes logged are the bytes sent
    before = settled(log.read_text)  # the /healthz requests of start(), waiting for the server
    requests = [
        lambda: server.get("/api/jobs?limit=5&state=queued", headers=plain),
        lambda: server.get("/healthz", headers=plain),
        lambda: server.get("/index.html", headers=plain),
        lambda: server.get("/no/such/thing", headers=plain),
        lambda: server.post("/api/jobs", data="{}",
                            headers={"Content-Type": "text/plain", **plain}),
        lambda: server.get("/api/jobs", headers={"Host": "evil.example", **plain}),
    ]
    responses = []
    for send in requests:
        # Each on a connection of its own, served by either of two threads: a line is written
        # after its response is sent, so wait for it before the next request to keep the order.
        responses.append(send())
        logged(log.read_text, before + len(responses))
    assert [r.status_code for r in responses] == [200, 200, 200, 404, 415, 403]
    job = submit_ok(server, JOB)
    logged(log.read_text, before + len(responses) + 1)
    run_to_end(server, job["id"])  # an event stream, logged when it ends
    expected = [(r.request.method, r.request.path_url.split("?")[0], r.status_code)
                for r in responses]
    expected += [("POST", "/api/jobs", 202), ("GET", f"/api/jobs/{job['id']}/events", 200)]
    lines = logged(log.read_text, before + len(expected))[before:]
    assert [(l["method"], l["path"], int(l["status"])) for l in lines] == expected, lines
    for line, r in zip(lines, responses):
        assert line["peer"].startswith("127.0.0.1:"), line
        assert int(line["bytes"]) == len(r.content), (line, len(r.content))
        assert float(line["ms"]) >= 0, line
    assert lines[-1]["bytes"] == "-"  # a streamed body
    assert "limit" not in log.read_text()  # no query string
    # The messages stay on stderr: the access log has nothing else.
    assert all(ACCESS_LINE.match(l) for l in log.read_text().splitlines())


def test_access_log_goes_to_stderr_by_default(start_server):
    server = start_server("--threads", "2")
    r = server.get(f"/api/jobs/{UNKNOWN_ID}")
    assert r.status_code == 404
    # Two lines: the start-up probe's /healthz and this request, in either order (each is written
    # once its response has gone out, by the thread that served it).
    lines = logged(server.log, 2)
    mine = [l for l in lines if l["path"] == f"/api/jobs/{UNKNOWN_ID}"]
    assert len(mine) == 1, lines
    assert {"method": "GET", "path": f"/api/jobs/{UNKNOWN_ID}", "status": "404",
            "bytes": str(len(r.content))} == {k: mine[0][k] for k in ("method", "path", "status",
                                                                     "bytes")}, lines
    server.stop()


def test_log_level_warning_silences_the_access_log(start_server):
    server = start_server("--threads", "2", "--log-level", "warning")
    assert server.get("/healthz").status_code == 200
    server.stop()  # every line is written by now
    assert access_lines(server.log()) == []
    assert "stopping" not in server.log()  # an info message
