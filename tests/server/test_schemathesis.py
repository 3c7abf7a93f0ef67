"""The OpenAPI document (server/http/openapi.json) is a valid OpenAPI 3.0 document, and the live
server keeps to it: schemathesis generates requests for every operation (valid and invalid ones,
and sequences that follow the document's links from a submitted job to its resources) and checks
every response: never a 5xx, statuses, content types, headers and bodies as documented, and
POST/DELETE refused without the bearer token. Its coverage phase adds the boundary values of every
documented parameter.

The server under test has small limits so that generated jobs stay cheap. Environment:
CAUSTIC_ST_MAX_EXAMPLES (per operation, default 30), CAUSTIC_ST_SEED (default 1; "random" for a
new one each run)."""

import json
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest
from openapi_spec_validator import validate

from conftest import ROOT

DOCUMENT = os.path.join(ROOT, "server", "http", "openapi.json")
TOKEN = "schemathesis-token"


def test_openapi_document_is_valid():
    with open(DOCUMENT, encoding="utf-8") as f:
        spec = json.load(f)
    validate(spec)  # raises on any violation of the OpenAPI 3.0 schema
    ids = [op["operationId"] for path in spec["paths"].values()
           for method, op in path.items() if method != "parameters"]
    assert len(ids) == len(set(ids)) == 21, ids
    for path in spec["paths"].values():
        for method, op in path.items():
            if method == "parameters":
                continue
            for status, response in op["responses"].items():
                if status.startswith("4") or status.startswith("5"):
                    content = response["content"]
                    assert list(content) == ["application/problem+json"], (op["operationId"],
                                                                            status)


@pytest.mark.timeout(420)
def test_schemathesis(start_server, tmp_path):
    # With a token, so that the `ignored_auth` check has something to find: POST and DELETE
    # without it must be 401 (schemathesis sends it everywhere else). 512x512 lets the document's
    # example job (the Cornell box by name, 1 spp) be accepted.
    server = start_server("--threads", "2", "--token", TOKEN, "--max-spp", "64",
                          "--max-resolution", "512", "--max-pixels", str(512 * 512),
                          "--max-time-limit", "5", "--max-queued", "20", "--max-photons", "100000")
    max_examples = os.environ.get("CAUSTIC_ST_MAX_EXAMPLES", "30")
    seed = os.environ.get("CAUSTIC_ST_SEED", "1")
    junit = tmp_path / "schemathesis.xml"
    st = os.path.join(os.path.dirname(sys.executable), "st")
    command = [st, "run", server.url("/api/openapi.json"), "--base-url", server.base,
               "--header", f"Authorization: Bearer {TOKEN}",
               "--checks", "all", "--hypothesis-max-examples", max_examples,
               "--hypothesis-deadline", "None", "--request-timeout", "30000",
               "--stateful", "links", "--experimental", "coverage-phase",
               "--junit-xml", str(junit), "--show-trace", "--no-color"]
    if seed != "random":
        command += ["--hypothesis-seed", seed]
    # The hooks send the mesh media types of POST /api/assets as raw bytes.
    env = dict(os.environ, SCHEMATHESIS_TELEMETRY="false",
               SCHEMATHESIS_HOOKS="schemathesis_hooks",
               PYTHONPATH=os.pathsep.join(filter(None, [os.path.dirname(os.path.abspath(__file__)),
                                                        os.environ.get("PYTHONPATH")])))
    proc = subprocess.run(command, capture_output=True, text=True, timeout=400, env=env,
                          cwd=tmp_path)
    output = proc.stdout + proc.stderr
    print(output)
    summary = os.environ.get("CAUSTIC_ST_SUMMARY")
    if summary:
        with open(summary, "w", encoding="utf-8") as f:
            f.write(output)
    assert proc.returncode == 0, "schemathesis found failures (output above)"
    assert server.alive(), server.log()
    server.healthy()
    # Every operation ran, and the server never answered 5xx.
    suite = ET.parse(junit).getroot()
    cases = suite.findall(".//testcase")
    assert len(cases) >= 15, [c.get("name") for c in cases]
    assert not suite.findall(".//failure") and not suite.findall(".//error")
    m = re.search(r"not_a_server_error\s+(\d+) / (\d+) passed", output)
    assert m and m.group(1) == m.group(2) and int(m.group(2)) > 0, "no not_a_server_error summary"
