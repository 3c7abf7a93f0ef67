#!/usr/bin/env python3
"""From upload to the first preview of a textured glTF model of a million triangles (issue 39):
how long a user waits between sending the file and seeing a picture of it.

Writes a .glb here (a UV sphere of --triangles triangles with normals and texture coordinates,
textured with assets/meshes/tiles.png, no light: the default environment), starts `caustic serve`
(SQLite, a temporary data folder, every core), and times, --rounds times with a fresh server each:
the upload (POST /api/assets: validated, imported counting only, stored), the job's admission
(POST /api/jobs naming it, the automatic camera, 512 pixels wide, `draft`), and the first preview
(GET /api/jobs/{id}/preview.png until it is 200: the worker imports the model in full, decodes the
texture, builds the accelerator and renders the first pass). Prints a Markdown table of the median
and the spread. Standard-library Python only; stops what it started.

usage: bench/gltf_first_preview.py [--binary PATH] [--triangles N] [--rounds N]
"""
import argparse
import http.client
import json
import math
import os
import shlex
import shutil
import struct
import sys
import tempfile
import time
from array import array

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from event_delay import start, stop  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def sphere_glb(triangles, texture):
    """A UV sphere of about `triangles` triangles (rings x 2 rings segments), positions, normals,
    texture coordinates and UNSIGNED_INT indices, textured with the PNG `texture`."""
    rings = max(2, int(math.sqrt(triangles / 4)))
    segments = 2 * rings
    pos, nrm, uv, idx = array("f"), array("f"), array("f"), array("I")
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            p = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            pos.extend(p)
            nrm.extend(p)
            uv.extend((4 * s / segments, 2 * r / rings))
    for r in range(rings):
        for s in range(segments):
            a, b = r * (segments + 1) + s, (r + 1) * (segments + 1) + s
            idx.extend((a, b, a + 1, a + 1, b, b + 1))
    blobs = [pos.tobytes(), nrm.tobytes(), uv.tobytes(), idx.tobytes(), texture]
    views, offset = [], 0
    for blob in blobs:
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(blob)})
        offset += (len(blob) + 3) // 4 * 4
    vertices = len(pos) // 3
    doc = {
        "asset": {"version": "2.0", "generator": "bench/gltf_first_preview.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                    "indices": 3, "material": 0}]}],
        "materials": [{"name": "Tiles", "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 0.5}}],
        "textures": [{"source": 0}],
        "images": [{"bufferView": 4, "mimeType": "image/png"}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": vertices, "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": vertices, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": vertices, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
        "bufferViews": views, "buffers": [{"byteLength": offset}]}
    bin_ = b"".join(blob + b"\0" * (-len(blob) % 4) for blob in blobs)
    chunk = json.dumps(doc).encode()
    chunk += b" " * (-len(chunk) % 4)
    body = (struct.pack("<II", len(chunk), 0x4E4F534A) + chunk +
            struct.pack("<II", len(bin_), 0x004E4942) + bin_)
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body, len(idx) // 3


def request(port, method, path, body=None, headers=None):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    conn.request(method, path, body=body, headers=headers or {})
    r = conn.getresponse()
    data = r.read()
    conn.close()
    return r.status, data


def one_round(binary, glb, tmp, i):
    server, m = start([binary, "serve", "--port", "0", "--data", os.path.join(tmp, f"data{i}")],
                      os.path.join(tmp, f"serve{i}.out"), r"serving on http://127\.0\.0\.1:(\d+)/")
    try:
        port = int(m.group(1))
        t0 = time.perf_counter()
        status, data = request(port, "POST", "/api/assets?name=sphere.glb", glb,
                               {"Content-Type": "model/gltf-binary"})
        assert status == 201, data[:300]
        asset = json.loads(data)["id"]
        t1 = time.perf_counter()
        job = {"scene": {"gltf": {"asset": asset}, "camera": {"auto": {}, "width": 512}},
               "settings": {"preset": "draft"}}
        status, data = request(port, "POST", "/api/jobs", json.dumps(job),
                               {"Content-Type": "application/json"})
        assert status == 202, data[:300]
        job_id = json.loads(data)["id"]
        t2 = time.perf_counter()
        while True:
            status, _ = request(port, "GET", f"/api/jobs/{job_id}/preview.png")
            if status == 200:
                break
            assert status == 404, status
            time.sleep(0.01)
        t3 = time.perf_counter()
        return t1 - t0, t2 - t1, t3 - t2, t3 - t0
    finally:
        stop(server)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--binary", default=os.path.join(REPO, "build", "cli", "caustic"))
    p.add_argument("--triangles", type=int, default=1_000_000)
    p.add_argument("--rounds", type=int, default=5)
    a = p.parse_args()
    with open(os.path.join(REPO, "assets", "meshes", "tiles.png"), "rb") as f:
        glb, triangles = sphere_glb(a.triangles, f.read())
    tmp = tempfile.mkdtemp(prefix="caustic-gltf-preview-", dir="/tmp")
    try:
        rounds = [one_round(a.binary, glb, tmp, i) for i in range(a.rounds)]
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"`{shlex.join(sys.argv)}`, {time.strftime('%Y-%m-%d')}, nproc {os.cpu_count()}: a "
          f".glb of {triangles} triangles ({len(glb) / 1e6:.1f} MB, one 512 x 512 PNG texture), "
          f"{a.rounds} rounds, a fresh server each\n")
    print("| step | median s | min s | max s |")
    print("|---|---:|---:|---:|")
    names = ["upload (validated, imported, stored)", "job admission", "first preview after admission",
             "upload to first preview"]
    for k, name in enumerate(names):
        values = sorted(r[k] for r in rounds)
        print(f"| {name} | {values[len(values) // 2]:.3f} | {values[0]:.3f} | {values[-1]:.3f} |")


if __name__ == "__main__":
    main()
