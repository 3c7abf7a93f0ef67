"""HTTPS (--tls-cert, --tls-key) and the token from a file (--token-file): a bearer token sent over
plain HTTP off loopback can be read by anyone on the path. The certificate is made by the openssl
command for 127.0.0.1, and the client trusts exactly it."""

import subprocess
import tempfile

import pytest
import requests

from conftest import TIMEOUT, TINY_SCENE, assert_problem

JOB = {"scene": TINY_SCENE, "settings": {"spp": 4}}

TOKEN = "s3cret-token-for-tls"


@pytest.fixture(scope="module")
def certificate():
    """(certificate, key) PEM files for 127.0.0.1 and localhost, valid for a day."""
    folder = tempfile.TemporaryDirectory(prefix="caustic-tls-")
    cert, key = f"{folder.name}/cert.pem", f"{folder.name}/key.pem"
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1",
                    "-subj", "/CN=127.0.0.1", "-addext",
                    "subjectAltName=IP:127.0.0.1,DNS:localhost", "-keyout", key, "-out", cert],
                   check=True, capture_output=True, timeout=60)
    yield cert, key
    folder.cleanup()


@pytest.fixture(scope="module")
def tls_server(start_server, certificate, tmp_path_factory):
    cert, key = certificate
    token_file = tmp_path_factory.mktemp("secret") / "token"
    token_file.write_text(TOKEN + "\n")
    s = start_server("--tls-cert", cert, "--tls-key", key, "--token-file", str(token_file),
                     "--threads", "2", verify=cert)
    yield s
    s.stop()


def test_the_server_says_https_and_answers_over_tls(tls_server):
    assert tls_server.base.startswith("https://127.0.0.1:")
    r = tls_server.get("/healthz")
    assert r.status_code == 200 and r.json() == {"status": "ok"}


def test_plain_http_gets_no_answer(tls_server):
    with pytest.raises(requests.exceptions.ConnectionError):
        requests.get(tls_server.base.replace("https://", "http://") + "/healthz", timeout=TIMEOUT)


def test_a_client_that_does_not_trust_the_certificate_is_refused(tls_server):
    with pytest.raises(requests.exceptions.SSLError):
        requests.get(tls_server.url("/healthz"), timeout=TIMEOUT, verify=True)


def test_the_token_from_the_file_guards_changes(tls_server):
    assert_problem(tls_server.submit(JOB), 401)
    r = tls_server.submit(JOB, headers={"Authorization": f"Bearer {TOKEN}"})
    assert r.status_code == 202, r.text
    tls_server.wait(r.json()["id"], {"succeeded"})
    image = tls_server.get(f"/api/jobs/{r.json()['id']}/image.exr")
    assert image.status_code == 200 and image.content[:4] == b"\x76\x2f\x31\x01"


def test_the_page_of_the_server_is_its_https_origin(tls_server):
    auth = {"Authorization": f"Bearer {TOKEN}"}
    own = tls_server.submit(JOB, headers={**auth, "Origin": tls_server.base})
    assert own.status_code == 202, own.text
    plain = tls_server.submit(JOB, headers={**auth, "Origin": tls_server.base.replace("https", "http")})
    assert_problem(plain, 403)


def run_serve(caustic_bin, *args):
    with tempfile.TemporaryDirectory() as data:
        return subprocess.run([caustic_bin, "serve", "--port", "0", "--data", data, *args],
                              capture_output=True, text=True, timeout=30)


def test_a_certificate_without_its_key_is_a_usage_error(caustic_bin, certificate):
    result = run_serve(caustic_bin, "--tls-cert", certificate[0])
    assert result.returncode != 0
    assert "--tls-key" in result.stderr, result.stderr


def test_a_key_that_is_not_the_certificates_stops_the_server(caustic_bin, certificate,
                                                               tmp_path):
    other = tmp_path / "other.pem"
    subprocess.run(["openssl", "genrsa", "-out", str(other), "2048"], check=True,
                   capture_output=True, timeout=60)
    result = run_serve(caustic_bin, "--tls-cert", certificate[0], "--tls-key", str(other))
    assert result.returncode == 1
    assert "cannot use the TLS certificate" in result.stderr, result.stderr


def test_a_token_file_must_hold_a_token(caustic_bin, tmp_path):
    empty = tmp_path / "empty"
    empty.write_text("\n")
    result = run_serve(caustic_bin, "--token-file", str(empty))
    assert result.returncode != 0 and "holds no token" in result.stderr, result.stderr
    result = run_serve(caustic_bin, "--token-file", str(tmp_path / "missing"))
    assert result.returncode != 0 and "cannot read a token" in result.stderr, result.stderr
    token = tmp_path / "token"
    token.write_text("t\n")
    result = run_serve(caustic_bin, "--token", "a", "--token-file", str(token))
    assert result.returncode != 0 and "excludes" in result.stderr, result.stderr


def test_caustic_health_asks_healthz_over_http_and_https(caustic_bin, server, tls_server):
    for base in (server.base, tls_server.base):
        r = subprocess.run([caustic_bin, "health", "--url", base + "/healthz"],
                           capture_output=True, text=True, timeout=30)
        assert r.returncode == 0, r.stderr
    # A port nothing listens on, and a path that is not 200.
    r = subprocess.run([caustic_bin, "health", "--url", "http://127.0.0.1:1/healthz",
                        "--timeout", "2"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 1 and "caustic health: http://127.0.0.1:1/healthz" in r.stderr, r.stderr
    r = subprocess.run([caustic_bin, "health", "--url", server.base + "/nothing"],
                       capture_output=True, text=True, timeout=30)
    assert r.returncode == 1 and "answered 404" in r.stderr, r.stderr
    r = subprocess.run([caustic_bin, "health", "--url", "127.0.0.1:8080"],
                       capture_output=True, text=True, timeout=30)
    assert r.returncode == 2 and "--url" in r.stderr, r.stderr
