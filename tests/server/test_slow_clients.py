"""Slow clients (issue 41; server/http/connection_gate.h): connections that send their request a
byte at a time hold no request thread, one address holds at most --max-connections-per-client
connections, a head or body that comes too slowly is cut, and /healthz answers throughout.

Before the gate, 90 connections sending a header line every few seconds took all of cpp-httplib's
80 request threads, and /healthz timed out for as long as they went on."""

import socket
import threading
import time

import requests

from conftest import TIMEOUT, submit_ok

HEAD = b"GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n"


def metric(server, name):
    text = server.get("/metrics").text
    for line in text.splitlines():
        if line.startswith(name + " "):
            return float(line.split()[-1])
    raise AssertionError(f"no {name} in /metrics")


def open_slow(server, sources):
    """One connection from each source address, each having sent the start of a request head."""
    socks = []
    for source in sources:
        s = socket.create_connection(("127.0.0.1", server.port), timeout=5,
                                     source_address=(source, 0))
        s.sendall(HEAD)
        socks.append(s)
    return socks


def answer_or_close(s, wait):
    """What the server did with a connection within `wait` seconds: its first bytes, b"" when it
    closed it, or None when it is still open and silent."""
    s.settimeout(wait)
    try:
        return s.recv(4096)
    except socket.timeout:
        return None
    except OSError:
        return b""


def healthz_seconds(server):
    """A fresh connection from 127.0.0.1 asks /healthz; returns how long the answer took."""
    start = time.monotonic()
    r = requests.get(server.url("/healthz"), timeout=5)
    assert r.status_code == 200, r.text
    return time.monotonic() - start


def drip_and_probe(server, socks, seconds):
    """Sends a header line on every slow connection every 3 seconds, and asks /healthz at once,
    halfway and at the end; returns the /healthz times."""
    times = []
    start = time.monotonic()
    probes = [1.0, seconds / 2, seconds]
    while probes:
        if time.monotonic() - start >= probes[0]:
            probes.pop(0)
            times.append(healthz_seconds(server))
        for s in socks:
            try:
                s.send(b"X-Slow: 1\r\n")
            except OSError:
                pass
        time.sleep(min(3.0, max(0.0, start + (probes[0] if probes else 0) - time.monotonic())))
    return times


def test_one_address_holds_at_most_its_share_and_healthz_answers(start_server):
    server = start_server("--threads", "1")
    socks = open_slow(server, ["127.0.0.2"] * 90)
    try:
        # Connections past the 32nd from one address are answered 429 on arrival.
        answers = [answer_or_close(s, 0.2) for s in socks]
        refused = [a for a in answers if a and a.startswith(b"HTTP/1.1 429")]
        assert len(refused) == 90 - 32, answers[:3]
        assert b"--max-connections-per-client" in refused[0]
        held = [s for s, a in zip(socks, answers) if a is None]
        assert len(held) == 32
        times = drip_and_probe(server, held, 14)
        print("healthz seconds beside 90 slow connections from one address:", times)
        assert max(times) < 1.0, times
        # Each held head ran past --request-head-seconds (10) and was closed.
        assert all(answer_or_close(s, 1) in (b"",) for s in held)
        assert metric(server, 'caustic_http_connections_refused_total{reason="per_client"}') >= 58
        assert metric(server, 'caustic_http_requests_cut_total{reason="head"}') >= 32
    finally:
        for s in socks:
            s.close()


def test_slow_heads_from_many_addresses_hold_no_thread(start_server):
    """100 addresses, one slow connection each: more than the 80 request threads, and no
    per-client cap applies. Waiting heads cost the gate a descriptor each, not a thread."""
    server = start_server("--threads", "1")
    socks = open_slow(server, [f"127.0.1.{i}" for i in range(1, 101)])
    try:
        times = drip_and_probe(server, socks, 14)
        print("healthz seconds beside 100 slow connections from 100 addresses:", times)
        assert max(times) < 1.0, times
        assert all(answer_or_close(s, 1) == b"" for s in socks)
        assert metric(server, "caustic_http_busy_threads") <= 2  # the /metrics request's own
    finally:
        for s in socks:
            s.close()


def job_body(size):
    """A valid job padded with spaces to `size` bytes."""
    body = (b'{"scene": "cornell-box", "settings": {"width": 16, "height": 16, "spp": 1}}')
    return body + b" " * (size - len(body))


def post_head(length):
    return (b"POST /api/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
            b"Content-Length: " + str(length).encode() + b"\r\n\r\n")


def test_a_body_slower_than_the_minimum_rate_is_cut(start_server):
    server = start_server("--threads", "1", "--request-head-seconds", "2",
                          "--min-body-rate", "4096")
    body = job_body(100000)
    s = socket.create_connection(("127.0.0.1", server.port), timeout=5)
    try:
        # 20000 bytes at once (past what waits in the gate), then a byte a second: the deadline
        # is 2 s + 20000 / 4096 s after the head, about 7 s.
        s.sendall(post_head(len(body)) + body[:20000])
        start = time.monotonic()
        closed = None
        for i in range(20000, 20030):
            try:
                s.send(body[i:i + 1])
            except OSError:
                closed = time.monotonic() - start
                break
            if answer_or_close(s, 1.0) == b"":
                closed = time.monotonic() - start
                break
        assert closed is not None and 5 < closed < 12, closed
        assert metric(server, 'caustic_http_requests_cut_total{reason="body"}') == 1
        server.healthy()
    finally:
        s.close()


def test_a_body_at_the_minimum_rate_is_served(start_server):
    server = start_server("--threads", "1", "--request-head-seconds", "2",
                          "--min-body-rate", "4096")
    body = job_body(60000)
    s = socket.create_connection(("127.0.0.1", server.port), timeout=TIMEOUT)
    try:
        # 20000 bytes a second for 3 seconds: above the minimum rate throughout.
        s.sendall(post_head(len(body)))
        for i in range(0, len(body), 20000):
            s.sendall(body[i:i + 20000])
            time.sleep(1.0)
        answer = s.recv(4096)
        assert answer.startswith(b"HTTP/1.1 202"), answer[:200]
        assert metric(server, 'caustic_http_requests_cut_total{reason="body"}') == 0
    finally:
        s.close()


def test_event_streams_beyond_the_limit_are_refused_all_at_once(start_server):
    """The limit is counted before it is checked: 16 streams opened together get exactly 4 in."""
    server = start_server("--threads", "1", "--max-event-streams", "4")
    job = submit_ok(server, {"scene": "cornell-box",
                             "settings": {"spp": 4096, "spp_per_pass": 1, "time_limit": 60}})
    statuses = []
    lock = threading.Lock()
    go = threading.Barrier(16)
    socks = []

    def follow():
        s = socket.create_connection(("127.0.0.1", server.port), timeout=10)
        with lock:
            socks.append(s)
        go.wait()
        s.sendall(f"GET /api/jobs/{job['id']}/events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"
                  .encode())
        status = s.recv(64).split(b" ")[1]
        with lock:
            statuses.append(int(status))

    threads = [threading.Thread(target=follow) for _ in range(16)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(30)
    try:
        assert sorted(statuses) == [200] * 4 + [429] * 12, statuses
        assert metric(server, "caustic_event_streams") == 4
    finally:
        for s in socks:
            s.close()
        server.post(f"/api/jobs/{job['id']}/cancel")
