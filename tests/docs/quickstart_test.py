#!/usr/bin/env python3
"""The README's quick start runs as written.

README.md marks its quick-start blocks with an HTML comment on the line before each fence
(`<!-- quickstart: setup -->`, `cli`, `http`, `gltf_cli`, `gltf_http`). This runs them in order
against this checkout (in CI, a fresh clone):
  setup  its first command (`bash scripts/run.sh`: install, build, serve) in the background, until
         the service prints its URL; the second (`bash scripts/test.sh`) is what CI is running now,
         and .ci/run must be that command;
  cli    in a scratch folder, then checks the PNG it wrote;
  http   the same, against the service; then the page (GET /) answers;
  gltf_cli and gltf_http  as cli and http, rendering the example glTF model.
Four substitutions keep a test from touching the user's things: `./build/` is this build folder,
`assets/models/` the checkout's, port 8080 a free port, and run.sh gets `--data` in the scratch
folder (its extra arguments go to `caustic serve`, as the README says). Each step is bounded in
time.

usage: quickstart_test.py SOURCE_DIR BUILD_DIR
"""
import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def blocks(readme):
    """{name: [lines]} of every fenced block after a `<!-- quickstart: name -->` line."""
    found, lines = {}, readme.splitlines()
    for i, line in enumerate(lines):
        m = re.match(r"^<!-- quickstart: (\w+) -->$", line)
        if not m:
            continue
        assert lines[i + 1].startswith("```"), f"README.md:{i + 2}: a fence must follow {line}"
        end = lines.index("```", i + 2)
        found[m.group(1)] = lines[i + 2:end]
    return found


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_block(name, lines, cwd, build, port, timeout):
    models = Path(__file__).resolve().parents[2] / "assets" / "models"
    script = ("\n".join(lines).replace("./build/", f"{build}/").replace(":8080", f":{port}")
              .replace("@assets/models/", f"@{models}/").replace(" assets/models/", f" {models}/"))
    print(f"--- quickstart {name}:\n{script}", flush=True)
    r = subprocess.run(["bash", "-euo", "pipefail", "-c", script], cwd=cwd, timeout=timeout,
                       stdin=subprocess.DEVNULL, capture_output=True, text=True)
    print(r.stdout[-2000:], r.stderr[-2000:], sep="\n", flush=True)
    assert r.returncode == 0, f"the {name} block exited with {r.returncode}"


def is_png(path):
    return path.is_file() and path.read_bytes()[:8] == PNG_SIGNATURE


def run_png_block(name, lines, scratch, build, port):
    """Runs the block in `scratch`, which must then hold PNG images only; removes them."""
    run_block(name, lines, scratch, build, port, timeout=300)
    pngs = [p for p in scratch.glob("*.png")]
    assert pngs and all(is_png(p) for p in pngs), f"the {name} block wrote {pngs}"
    for p in pngs:
        p.unlink()


def main():
    source, build = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve()
    found = blocks((source / "README.md").read_text(encoding="utf-8"))
    assert set(found) == {"setup", "cli", "http", "gltf_cli", "gltf_http"}, \
        f"quick-start blocks found: {sorted(found)}"
    setup = [line.split("#")[0].strip() for line in found["setup"]]
    assert setup == ["bash scripts/run.sh", "bash scripts/test.sh"], setup
    assert "scripts/test.sh" in (source / ".ci" / "run").read_text(), ".ci/run runs scripts/test.sh"

    port = free_port()
    with tempfile.TemporaryDirectory(prefix="caustic-quickstart-") as scratch:
        scratch = Path(scratch)
        for name in ("cli", "gltf_cli"):
            run_png_block(name, found[name], scratch, build, port)

        env = dict(os.environ, CAUSTIC_BUILD_DIR=str(build))
        server = subprocess.Popen(
            ["bash", "scripts/run.sh", "--port", str(port), "--data", str(scratch / "data")],
            cwd=source, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT, text=True, start_new_session=True)
        try:
            # install-deps finds everything installed and the build is up to date: the URL comes
            # within seconds, but a slow disk may take a minute to check the build.
            deadline, url = time.monotonic() + 600, None
            for line in server.stdout:
                print(line, end="", flush=True)
                m = re.search(r"serving on (http://\S+/)", line)
                if m:
                    url = m.group(1)
                    break
                assert time.monotonic() < deadline, "run.sh printed no URL in 600 s"
            assert url == f"http://127.0.0.1:{port}/", f"run.sh printed {url}"
            for name in ("http", "gltf_http"):
                run_png_block(name, found[name], scratch, build, port)
            with urllib.request.urlopen(url, timeout=10) as page:
                assert page.status == 200 and b"<title>" in page.read()
        finally:
            os.killpg(server.pid, signal.SIGINT)
            try:
                server.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(server.pid, signal.SIGKILL)
                server.wait()
    print("quickstart: the setup, cli, http, gltf_cli and gltf_http blocks ran as written")


if __name__ == "__main__":
    main()
