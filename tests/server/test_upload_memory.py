"""Uploads are held to their limits while they are read and parsed, not after: a small file that
expands (a .glb instancing one mesh 65 thousand times, an OBJ of millions of unused vertices) is
refused before it takes the memory, and a declared length takes none before its bytes arrive.

Each test prints the server's peak resident memory (VmHWM, reset before the upload through
/proc/PID/clear_refs) for the record; run with -s to see it."""

import socket
import time

import pytest

from conftest import assert_problem
from test_assets import GLB, OBJ, glb_bytes, glb_document, upload, upload_ok

MIB = 1 << 20


def status(server, field):
    """A field of /proc/PID/status of the server, in bytes."""
    with open(f"/proc/{server.proc.pid}/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    raise KeyError(field)


def reset_peak(server):
    # "5" resets the peak resident set size (proc(5), /proc/pid/clear_refs).
    with open(f"/proc/{server.proc.pid}/clear_refs", "w") as f:
        f.write("5")


def peak_growth(server, what, send):
    """Runs `send` and prints how far the server's peak resident memory rose above where it was."""
    reset_peak(server)
    before = status(server, "VmRSS")
    start = time.monotonic()
    result = send()
    seconds = time.monotonic() - start
    growth = status(server, "VmHWM") - before
    print(f"\n{what}: {getattr(result, 'status_code', result)} in {seconds:.2f} s, "
          f"server peak resident memory +{growth / MIB:.1f} MiB")
    return result, growth


def instancing_glb(nodes, quads_per_mesh):
    """A .glb of one mesh of `quads_per_mesh` copies of the unit quad (4 vertices), drawn by
    `nodes` nodes: a few bytes a node, 2 * quads_per_mesh triangles each once instanced."""
    indices = [0, 1, 2, 0, 2, 3] * quads_per_mesh
    doc = glb_document(
        scenes=[{"nodes": list(range(nodes))}],
        nodes=[{"mesh": 0}] * nodes)
    doc["accessors"][1]["count"] = len(indices)
    doc["bufferViews"][1]["byteLength"] = 2 * len(indices)
    doc["buffers"][0]["byteLength"] = 48 + 2 * len(indices)
    return glb_bytes(doc, indices=indices)


def test_an_instancing_glb_is_refused_before_it_expands(server):
    # 65000 nodes of one 320-triangle mesh: 20.8 million triangles, over the default 20 million
    # of --max-asset-triangles, from a file of about a megabyte.
    data = instancing_glb(65000, 160)
    assert len(data) < 2 * MIB
    r, growth = peak_growth(server, f"instancing .glb of {len(data)} bytes, 20.8M triangles",
                            lambda: upload(server, data, media=GLB))
    assert_problem(r, 422, detail="over the limit of 20000000 triangles")
    # The nodes are counted before a triangle is built: what grows is the parsed glTF document
    # (65000 nodes), not the 20.8 million triangles (250 MB of indices alone).
    assert growth < 150 * MIB
    # The same file with fewer nodes is a mesh like any other.
    small = instancing_glb(1000, 160)
    assert upload_ok(server, small, media=GLB)["triangles"] == 320000
    server.healthy()


@pytest.fixture(scope="module")
def million(start_server):
    s = start_server("--threads", "2", "--max-asset-triangles", "1000000")
    yield s
    s.stop()


def test_an_obj_of_too_many_vertices_is_refused_at_the_line(million):
    # 4 million vertex lines and one face: 1 triangle, but 4 million vertices to keep. The limit
    # of 1 million triangles allows 3 million vertices (three corners each).
    data = b"v 0 0 0\n" * 4000000 + b"f 1 2 3\n"
    r, growth = peak_growth(million, f"OBJ of {len(data)} bytes, 4M vertices, 1 face",
                            lambda: upload(million, data))
    assert_problem(r, 422, detail="line 3000001: 3000001 vertices, over the limit of 3000000")
    # The line pass keeps counts: the body (32 MB) is all the upload holds.
    assert growth < 3 * len(data)
    r = upload(million, b"v 0 0 0\n" * 4 + b"vn 0 0 1\n" * 3000001 + b"f 1 2 3\n")
    assert_problem(r, 422, detail="3000001 normals, over the limit of 3000000")
    million.healthy()


def test_a_declared_length_takes_no_memory_before_its_bytes(server):
    # Four uploads (--max-uploads) each declaring the largest body (--max-asset-bytes, 256 MiB)
    # and sending a kilobyte: the buffers grow with what arrived.
    before = status(server, "VmSize")
    socks = []
    for i in range(4):
        sock = socket.create_connection(("127.0.0.1", server.port))
        sock.sendall(b"POST /api/assets HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: " +
                     OBJ.encode() + b"\r\nContent-Length: 268435456\r\n\r\n" +
                     b"v 0 0 0\n" * 128)
        socks.append(sock)
    time.sleep(1.5)
    grown = status(server, "VmSize") - before
    print(f"\n4 uploads declaring 256 MiB, 1 KiB sent: server address space +{grown / MIB:.1f} MiB")
    for sock in socks:
        sock.close()
    # glibc gives each new request thread a malloc arena of 64 MiB of address space: 4 uploads on
    # 4 threads may take 256 MiB of it, used or not; 4 buffers of the declared length, 1 GiB more.
    assert grown <= 4 * 64 * MIB
    server.healthy()
