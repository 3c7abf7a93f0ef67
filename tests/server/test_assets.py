"""Uploaded meshes (POST/GET/DELETE /api/assets) against the real server: the repository's OBJ
meshes and a .glb written here are uploaded (id = SHA-256 of the bytes, the same bytes once),
rendered from scenes that name them, held by the jobs that use them (409), kept across a restart,
and bad files and requests are refused, each with its status and problem detail."""

import hashlib
import http.client
import json
import os
import socket
import struct
import time

import pytest

from conftest import ROOT, TINY_SCENE, Server, assert_problem, run_to_end, submit_ok
from test_bad_input import RawResponse, send_raw

MESHES = os.path.join(ROOT, "assets", "meshes")
OBJ, GLB = "model/obj", "model/gltf-binary"
TRIANGLE_OBJ = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
UNKNOWN_ASSET = "ab" * 32
END_STATES = {"succeeded", "failed", "cancelled"}


def mesh(name):
    with open(os.path.join(MESHES, name), "rb") as f:
        return f.read()


def upload(server, data, media=OBJ, name=None, headers=None):
    """POST /api/assets with `data` as the body; media None sends no Content-Type."""
    headers = dict(headers or {})
    if media is not None:
        headers["Content-Type"] = media
    params = {"name": name} if name is not None else None
    return server.post("/api/assets", data=data, headers=headers, params=params)


def upload_ok(server, data, media=OBJ, name=None, status=201):
    r = upload(server, data, media, name)
    assert r.status_code == status, r.text
    asset = r.json()
    assert asset["id"] == hashlib.sha256(data).hexdigest()
    assert r.headers["Location"] == f"/api/assets/{asset['id']}"
    assert asset["bytes"] == len(data)
    assert asset["format"] == ("obj" if media == OBJ else "glb")
    assert set(asset) == {"id", "format", "name", "bytes", "triangles", "vertices", "bounds",
                          "created_at", "model"}
    assert (asset["model"] is None) == (media == OBJ)
    return asset


def stored(server, data, media=OBJ):
    """Uploads `data`, new (201) or stored by an earlier test (200)."""
    r = upload(server, data, media)
    assert r.status_code in (200, 201), r.text
    return r.json()


def headers_only(server, path, media, length):
    """POST with a Content-Length of `length` and no body: the answer the headers get."""
    return send_raw(server, (f"POST {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n"
                             f"Content-Type: {media}\r\nContent-Length: {length}\r\n\r\n").encode())


def padded_obj(size, tag):
    """A one-triangle OBJ of exactly `size` bytes, made distinct by `tag` in a comment."""
    head = TRIANGLE_OBJ + f"# {tag} ".encode()
    return head + b"x" * (size - len(head) - 1) + b"\n"


def asset_scene(*shapes):
    """TINY_SCENE with mesh shapes (dicts) inserted from /scene/shapes/1 on."""
    scene = json.loads(json.dumps(TINY_SCENE))
    scene["shapes"][1:1] = list(shapes)
    return scene


def asset_shape(asset_id, scale=0.5, translate=(0, -0.5, 0)):
    return {"type": "mesh", "asset": asset_id, "material": "white",
            "transform": {"scale": scale, "translate": list(translate)}}


# A .glb written here (glTF 2.0, "GLB File Format Specification"): one mesh of a unit quad (two
# triangles) instanced by two nodes, the second moved and scaled, all in its BIN chunk.
QUAD_POSITIONS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
QUAD_INDICES = [0, 1, 2, 0, 2, 3]


def glb_document(**change):
    """The glTF JSON of the quad .glb; `change` replaces top-level members."""
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0, "translation": [-1, 0, 0]},
                  {"mesh": 0, "translation": [2, 0, 0], "scale": [2, 2, 2]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
        "buffers": [{"byteLength": 60}],
    }
    doc.update(change)
    return doc


def glb_bytes(doc=None, indices=QUAD_INDICES, magic=b"glTF", version=2):
    """A .glb: 12-byte header, the JSON chunk (padded with spaces), the BIN chunk (zeros)."""
    json_chunk = json.dumps(doc if doc is not None else glb_document()).encode()
    json_chunk += b" " * (-len(json_chunk) % 4)
    bin_chunk = b"".join(struct.pack("<3f", *p) for p in QUAD_POSITIONS)
    bin_chunk += struct.pack(f"<{len(indices)}H", *indices)
    bin_chunk += b"\0" * (-len(bin_chunk) % 4)
    body = (struct.pack("<II", len(json_chunk), 0x4E4F534A) + json_chunk +
            struct.pack("<II", len(bin_chunk), 0x004E4942) + bin_chunk)
    return magic + struct.pack("<II", version, 12 + len(body)) + body


def glb_with(**change):
    return glb_bytes(glb_document(**change))


QUAD_GLB = glb_bytes()


# Uploads, reads, deduplication, paging.

def test_uploads_the_repository_meshes_and_a_glb(server):
    for name in ("teapot.obj", "spot.obj", "stanford-bunny.obj"):
        data = mesh(name)
        asset = upload_ok(server, data, name=name)
        assert asset["name"] == name
        assert asset["vertices"] == data.count(b"\nv ") + data.startswith(b"v ")
        assert asset["triangles"] >= data.count(b"\nf ")  # polygons make more than one
        lo, hi = asset["bounds"]["min"], asset["bounds"]["max"]
        assert all(a < b for a, b in zip(lo, hi)), asset
        assert server.get(f"/api/assets/{asset['id']}").json() == asset
    asset = upload_ok(server, QUAD_GLB, GLB, name="quads.glb")
    assert asset["triangles"] == 4  # two nodes instance the two-triangle quad
    # The nodes' transforms: [-1, 0] + the unit quad, and [2, 0] + the quad scaled by 2.
    assert asset["bounds"] == {"min": [-1, 0, 0], "max": [4, 2, 0]}, asset


def test_the_same_bytes_are_one_asset(server):
    data = padded_obj(200, "dedupe")
    first = upload_ok(server, data, name="first.obj")
    again = upload_ok(server, data, name="second.obj", status=200)
    assert again == first  # the name given first stays
    listed = [a for a in server.get("/api/assets?limit=100").json()["assets"]
              if a["id"] == first["id"]]
    assert listed == [first]


def test_lists_assets_newest_first_in_pages(server):
    ids = [upload_ok(server, padded_obj(120, f"page {i}"))["id"] for i in range(3)]
    page = server.get("/api/assets?limit=2").json()
    assert [a["id"] for a in page["assets"]] == ids[::-1][:2]
    rest = server.get(f"/api/assets?limit=2&cursor={page['next_cursor']}").json()
    assert rest["assets"][0]["id"] == ids[0]
    assert_problem(server.get("/api/assets?limit=0"), 400, detail="limit must be an integer")
    assert_problem(server.get("/api/assets?cursor=x"), 400, detail="cursor must be an integer")


# Rendering scenes that name assets.

def test_renders_scenes_with_obj_and_glb_assets(server):
    teapot = stored(server, mesh("teapot.obj"))
    quads = stored(server, QUAD_GLB, GLB)
    for shapes in ([asset_shape(teapot["id"], scale=0.2)],
                   [asset_shape(quads["id"], scale=0.2, translate=(-0.3, -0.3, 0))],
                   [asset_shape(teapot["id"], scale=0.1), asset_shape(quads["id"], scale=0.1)],
                   # One asset placed twice: its bytes are read once, each placement built.
                   [asset_shape(teapot["id"], scale=0.1),
                    asset_shape(teapot["id"], scale=0.1, translate=(0.4, 0, 0))]):
        job = submit_ok(server, {"scene": asset_scene(*shapes), "settings": {"spp": 2}})
        end = run_to_end(server, job["id"])
        assert end["state"] == "succeeded", end
        r = server.get(f"/api/jobs/{job['id']}/image.png")
        assert r.status_code == 200 and r.content.startswith(b"\x89PNG")


def test_an_asset_used_by_a_queued_or_running_job_is_not_deleted(server, long_job):
    asset = upload_ok(server, padded_obj(150, "held"))
    # The one worker renders long_job: this job waits in the queue.
    queued = submit_ok(server, {"scene": asset_scene(asset_shape(asset["id"])),
                                "settings": {"spp": 1}})
    assert server.job(queued["id"])["state"] == "queued"
    assert_problem(server.delete(f"/api/assets/{asset['id']}"), 409,
                   detail="used by a queued or running job")
    assert server.get(f"/api/assets/{asset['id']}").status_code == 200
    assert server.post(f"/api/jobs/{queued['id']}/cancel").status_code == 202
    assert server.wait(queued["id"], END_STATES)["state"] == "cancelled"
    assert server.delete(f"/api/assets/{asset['id']}").status_code == 204
    assert_problem(server.get(f"/api/assets/{asset['id']}"), 404, detail="no asset")


def test_a_running_job_holds_its_asset_until_it_ends(server):
    asset = stored(server, mesh("spot.obj"))
    job = submit_ok(server, {"scene": asset_scene(asset_shape(asset["id"])),
                             "settings": {"spp": 65536, "spp_per_pass": 1, "time_limit": 120}})
    server.wait(job["id"], {"running"})
    assert_problem(server.delete(f"/api/assets/{asset['id']}"), 409,
                   detail="used by a queued or running job")
    assert server.post(f"/api/jobs/{job['id']}/cancel").status_code == 202
    server.wait(job["id"], END_STATES)
    # A finished job keeps it until the job is deleted, or the asset is.
    assert server.delete(f"/api/jobs/{job['id']}").status_code == 204
    assert server.delete(f"/api/assets/{asset['id']}").status_code == 204
    server.healthy()


def test_assets_survive_a_restart(start_server):
    first = start_server("--threads", "2")
    asset = upload_ok(first, mesh("teapot.obj"), name="teapot.obj")
    glb = upload_ok(first, QUAD_GLB, GLB)
    first.stop()
    # A new process on the same data folder.
    second = Server(first.args[0], os.path.dirname(first.data), first.args[8:]).start()
    try:
        assert second.get(f"/api/assets/{asset['id']}").json() == asset
        assert upload_ok(second, QUAD_GLB, GLB, status=200) == glb
        job = submit_ok(second, {"scene": asset_scene(asset_shape(asset["id"], scale=0.2),
                                                      asset_shape(glb["id"], scale=0.1)),
                                 "settings": {"spp": 2}})
        assert run_to_end(second, job["id"])["state"] == "succeeded"
    finally:
        second.stop()


# Bad files: 422 with what the loader found.

BAD_FILES = [
    ("truncated OBJ", OBJ, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2", "truncated"),
    ("binary garbage", OBJ, bytes(range(256)) * 4, "binary data"),
    ("NaN vertex", OBJ, b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "line 2"),
    ("infinite vertex", OBJ, b"v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", "line 3"),
    ("vertex over a float", OBJ, b"v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n", "line 3"),
    ("index out of range", OBJ, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "out of range"),
    ("index 0", OBJ, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "vertex index 0"),
    ("vertex of two numbers", OBJ, b"v 0 0\nf 1 1 1\n", "line 1"),
    ("empty OBJ", OBJ, b"", "empty"),
    ("mtllib only", OBJ, b"mtllib ../../etc/passwd\n", "no faces"),
    ("no faces", OBJ, b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
    ("OBJ sent as glb", GLB, TRIANGLE_OBJ, "glTF"),
    ("empty GLB", GLB, b"", "empty"),
    ("GLB bad magic", GLB, b"glTX" + QUAD_GLB[4:], "glTF"),
    ("truncated GLB", GLB, QUAD_GLB[:-16], "truncated"),
    ("GLB version 1", GLB, glb_bytes(version=1), "version"),
    ("GLB buffer uri", GLB, glb_with(buffers=[{"byteLength": 60, "uri": "/etc/passwd"}]),
     "buffer 0"),
    ("GLB image uri", GLB, glb_with(images=[{"uri": "file:///etc/passwd"}]), "image 0"),
    ("GLB accessor out of range", GLB,
     glb_with(accessors=[{"bufferView": 0, "componentType": 5126, "count": 400,
                          "type": "VEC3"}, glb_document()["accessors"][1]]), "accessor 0"),
    ("GLB index out of range", GLB, glb_bytes(indices=[0, 1, 2, 0, 2, 9]), "accessor 1"),
    ("GLB missing accessor", GLB,
     glb_with(meshes=[{"primitives": [{"attributes": {"POSITION": 7}, "indices": 1}]}]),
     "accessor 7"),
    ("polygon of 257 corners", OBJ,
     b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf" + b" 1 2 3" * 85 + b" 1 2\n", "257 corners"),
    ("GLB of 65537 nodes", GLB, glb_with(nodes=[{}] * 65537), "65537 nodes"),
    # A fuzzing finding: tinygltf threw std::out_of_range for a buffer of 0 bytes with views (a
    # 500 then); tests/fuzz/mesh/empty-buffer-with-views.chunks.
    ("GLB buffer of 0 bytes with views", GLB, glb_with(buffers=[{"byteLength": 0}]),
     "outside what the file holds"),
    ("GLB lines, not triangles", GLB,
     glb_with(meshes=[{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1,
                                       "mode": 1}]}]), "mode"),
]


@pytest.mark.parametrize("media,data,detail", [case[1:] for case in BAD_FILES],
                         ids=[case[0] for case in BAD_FILES])
def test_bad_files_are_refused_with_what_is_wrong(server, media, data, detail):
    assert_problem(upload(server, data, media, name="bad"), 422, detail=detail)


# Bad requests.

@pytest.mark.parametrize("headers,data,detail", [
    ({"Content-Type": "application/json"}, b"{}", "model/obj or model/gltf-binary"),
    ({"Content-Type": "text/plain"}, TRIANGLE_OBJ, "text/plain"),
    ({}, TRIANGLE_OBJ, "Content-Type"),
    ({"Content-Type": "application/x-www-form-urlencoded"}, b"a=b", "model/obj"),
    ({"Content-Type": "model/gltf+json"}, b"{}", "model/gltf+json"),
], ids=["json", "text", "none", "form", "gltf-json"])
def test_other_media_types_are_415(server, headers, data, detail):
    r = server.post("/api/assets", data=data, headers=headers)
    assert_problem(r, 415, detail=detail)


def test_a_multipart_form_is_415(server):
    r = server.post("/api/assets", files={"file": ("mesh.obj", TRIANGLE_OBJ, OBJ)})
    assert_problem(r, 415, detail="multipart/form-data")


def test_the_same_bytes_in_another_format_are_refused(server):
    asset = upload_ok(server, TRIANGLE_OBJ)
    assert_problem(upload(server, TRIANGLE_OBJ, GLB), 422,
                   detail=f"these bytes are stored as asset {asset['id']} in the obj format, "
                          "not as glb")


def test_bad_names_ids_and_bodies(server):
    assert_problem(upload(server, TRIANGLE_OBJ, name="n" * 201), 400,
                   detail="over 200 characters")
    assert upload(server, padded_obj(100, "name"), name="é" * 200).json()["name"] == "é" * 200
    assert_problem(server.get(f"/api/assets/{UNKNOWN_ASSET}"), 404, detail="no asset")
    assert_problem(server.delete(f"/api/assets/{UNKNOWN_ASSET}"), 404, detail="no asset")
    assert_problem(server.get("/api/assets/ABC"), 404, detail="64 lowercase hex digits")
    assert_problem(server.delete("/api/assets/" + "A" * 64), 404,
                   detail="64 lowercase hex digits")
    # A chunked body has no Content-Length to check before it is read.
    with socket.create_connection(("127.0.0.1", server.port), timeout=10) as s:
        s.sendall(b"POST /api/assets HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: model/obj\r\n"
                  b"Transfer-Encoding: chunked\r\n\r\n4\r\nv 0 \r\n0\r\n\r\n")
        reply = s.recv(65536)
    assert reply.startswith(b"HTTP/1.1 411"), reply


def test_scenes_naming_bad_assets_are_422_at_the_field(server):
    scene = asset_scene(asset_shape(UNKNOWN_ASSET))
    assert_problem(server.submit({"scene": scene}), 422, "/scene/shapes/1/asset",
                   detail="no asset " + UNKNOWN_ASSET)
    scene = asset_scene(asset_shape("not-a-sha256"))
    assert_problem(server.submit({"scene": scene}), 422, "/scene/shapes/1/asset")
    asset = stored(server, TRIANGLE_OBJ)
    both = dict(asset_shape(asset["id"]), file="teapot.obj")
    r = server.submit({"scene": asset_scene(both)})
    problem = assert_problem(r, 422, r.json().get("pointer"))
    assert problem["pointer"].startswith("/scene/shapes/1"), problem
    assert "asset" in problem["detail"] and "file" in problem["detail"], problem


# Limits, each on a server of its own small ones.

@pytest.fixture(scope="module")
def small(start_server):
    s = start_server("--threads", "2", "--max-asset-bytes", "400000",
                     "--max-asset-triangles", "6000", "--max-asset-storage-mib", "1",
                     "--max-request-bytes", "100000")
    yield s
    s.stop()


def test_limits_of_size_triangles_and_storage(small):
    # Over --max-asset-bytes: refused from the Content-Length alone, before the body is read (a
    # client sending the body could lose the answer when the server closes the connection).
    bunny = len(mesh("stanford-bunny.obj"))
    assert_problem(headers_only(small, "/api/assets", OBJ, bunny), 413,
                   detail=f"has {bunny} bytes; this server takes at most 400000 (--max-asset-bytes)")
    # The limit is the upload's: a job body is held to --max-request-bytes.
    assert_problem(headers_only(small, "/api/jobs", "application/json", 200000), 413,
                   detail="at most 100000 (--max-request-bytes)")
    # Over --max-asset-triangles (teapot: 6320), and just under it (spot: 5856).
    assert_problem(upload(small, mesh("teapot.obj")), 422, detail="--max-asset-triangles")
    spot = upload_ok(small, mesh("spot.obj"))
    # Storage: 330624 + 390000 bytes fit in 1 MiB; another 390000 do not.
    upload_ok(small, padded_obj(390000, "fits"))
    assert_problem(upload(small, padded_obj(390000, "full")), 507,
                   detail="--max-asset-storage-mib")
    # Stored bytes are still found, and deleting frees the room.
    upload_ok(small, mesh("spot.obj"), status=200)
    assert small.delete(f"/api/assets/{spot['id']}").status_code == 204
    upload_ok(small, padded_obj(390000, "full"))
    small.healthy()


def answer(sock):
    """The response read off a raw socket, whole (its Content-Length), for assert_problem."""
    response = http.client.HTTPResponse(sock)
    response.begin()
    return RawResponse(response.status, response.headers, response.read())


def start_slow_upload(server, body):
    """A raw connection that has sent an upload's headers and the first 100 bytes of `body`."""
    sock = socket.create_connection(("127.0.0.1", server.port), timeout=10)
    sock.sendall(b"POST /api/assets HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: model/obj\r\n"
                 + f"Content-Length: {len(body)}\r\n\r\n".encode() + body[:100])
    return sock


def assert_busy(r):
    assert_problem(r, 429, detail="--max-uploads")
    assert r.headers["Retry-After"] == "5"


def slow_upload_held_its_place(server, attempt):
    """Starts an upload whose body trickles, and uploads small files until one is refused while it
    waits for the rest. False when the slow upload was refused itself (see below)."""
    body = padded_obj(5000, f"slow {attempt}")
    with start_slow_upload(server, body) as slow:
        # Its handler takes the one place before the body is read, and holds it while it waits
        # for the rest: another upload is refused once it has started.
        end = time.monotonic() + 8
        while True:
            r = upload(server, padded_obj(100, f"try {time.monotonic()}"))
            if r.status_code != 201 or time.monotonic() > end:
                break
            time.sleep(0.02)
        if r.status_code == 201:
            # None was refused in 8 s. The place is taken when the server reads the headers, and
            # a small upload may have held it then: the slow one was refused, and is told so once
            # its body has come (read and dropped, so that the connection carries the next).
            slow.sendall(body[100:])
            told = answer(slow)
            assert told.status_code == 429, (
                f"the slow upload never held its place; it was told {told.status_code} "
                f"{told.text}\n" + server.log())
            assert_busy(told)
            return False
        assert_busy(r)
        # While it holds the place, an upload that sends its body is refused after it.
        other = padded_obj(5000, f"other {attempt}")
        with start_slow_upload(server, other) as late:
            late.sendall(other[100:])
            assert_busy(answer(late))
            late.sendall(b"GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
            assert answer(late).status_code == 200
        slow.sendall(body[100:])
        stored_slow = answer(slow)
    assert stored_slow.status_code == 201, stored_slow.text
    assert stored_slow.json()["id"] == hashlib.sha256(body).hexdigest()
    return True


def test_uploads_over_max_uploads_in_flight_are_429(start_server):
    server = start_server("--threads", "2", "--max-uploads", "1")
    # Which of two uploads that come together gets the one place is up to the server's threads:
    # another try when a small one got it (1 try in 100 to 150 with three busy loops beside the
    # test on two cores; the slow upload is then told 429, and a single try would fail with "the
    # slow upload never held its place").
    assert any(slow_upload_held_its_place(server, attempt) for attempt in range(3)), (
        "the slow upload was refused 3 times in a row:\n" + server.log())
    upload_ok(server, padded_obj(100, "after"))
