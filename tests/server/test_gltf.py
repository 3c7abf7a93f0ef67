"""glTF files as scenes through the service (docs/gltf.md): a .glb written here is uploaded, its
asset lists what it holds as a scene, a job renders it by {"scene": {"gltf": {"asset": id}}} with
overrides, the job says which camera and environment it used, and bad files and overrides are
4xx naming the glTF object or the JSON path."""

import io
import json
import struct
import zipfile

from conftest import ROOT, assert_problem, run_to_end, submit_ok
from test_assets import (GLB, OBJ, QUAD_GLB, QUAD_INDICES, QUAD_POSITIONS, TRIANGLE_OBJ, glb_bytes,
                         glb_document, stored, upload)

# The quad file with a camera looking at it from +z and a point light in front of it.
LIT_GLB = glb_bytes(glb_document(
    nodes=[{"mesh": 0, "translation": [-1, 0, 0]},
           {"mesh": 0, "translation": [2, 0, 0], "scale": [2, 2, 2]},
           {"camera": 0, "name": "Front", "translation": [1, 1, 6]},
           {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [1, 1, 2]}],
    scenes=[{"nodes": [0, 1, 2, 3]}],
    cameras=[{"type": "perspective", "name": "Front",
              "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1}}],
    materials=[{"name": "Blue", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.3, 0.9, 1],
                                                         "metallicFactor": 0}}],
    meshes=[{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    extensionsUsed=["KHR_lights_punctual", "KHR_materials_sheen"],
    extensions={"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 2000,
                                                    "name": "Bulb"}]}}))


def gltf_job(asset_id, **scene):
    return {"scene": {"gltf": {"asset": asset_id}, **scene}, "settings": {"spp": 2}}


def test_a_glb_asset_lists_what_it_holds(server):
    asset = stored(server, LIT_GLB, GLB)
    model = server.get(f"/api/assets/{asset['id']}").json()["model"]
    assert model["triangles"] == 4 and model["draws"] == 2
    assert model["materials"] == ["Blue"]
    assert model["cameras"] == [{"name": "Front", "camera": 0, "node": 2}]
    assert model["lights"] == [{"name": "Bulb", "type": "point"}]
    assert model["extensions"]["used"] == ["KHR_lights_punctual", "KHR_materials_sheen"]
    assert model["warnings"] == ["the extension KHR_materials_sheen is not supported; ignored"]
    assert stored(server, glb_bytes(), GLB)["model"]["cameras"] == []


def test_renders_a_glb_through_its_camera_and_an_automatic_one(server):
    asset = stored(server, LIT_GLB, GLB)
    job = submit_ok(server, gltf_job(asset["id"], camera={"gltf": "Front", "width": 48}))
    assert job["model"]["camera"] == {"gltf": 0, "name": "Front"}
    assert job["model"]["environment"] is None  # the file has a light
    end = run_to_end(server, job["id"])
    assert end["state"] == "succeeded", end
    png = server.get(f"/api/jobs/{job['id']}/image.png").content
    assert png.startswith(b"\x89PNG")
    assert struct.unpack(">II", png[16:24]) == (48, 32)  # the camera's aspect ratio, 1.5
    # No camera and no light: the automatic camera and the white environment.
    quads = stored(server, glb_bytes(), GLB)
    job = submit_ok(server, gltf_job(quads["id"], camera={"auto": {"azimuth": 0}, "width": 40}))
    assert job["model"]["camera"] == {"auto": {"azimuth": 0.0, "elevation": 20.0, "fov": 40.0}}
    assert job["model"]["environment"] == {"color": [1.0, 1.0, 1.0]}
    assert run_to_end(server, job["id"])["state"] == "succeeded"


def test_overrides_change_materials_and_the_environment(server):
    asset = stored(server, LIT_GLB, GLB)
    job = submit_ok(server, gltf_job(asset["id"], camera={"gltf": 0, "width": 32},
                                     materials={"Blue": {"roughness": 0.2}},
                                     environment={"color": [0.2, 0.2, 0.2]}))
    assert job["model"]["environment"] == {"color": [0.2, 0.2, 0.2]}
    assert run_to_end(server, job["id"])["state"] == "succeeded"


def test_bad_models_and_overrides_are_4xx_at_their_path(server):
    asset = stored(server, LIT_GLB, GLB)
    assert_problem(server.post("/api/jobs", json=gltf_job(asset["id"], camera={"gltf": "Back"})),
                   422, detail="no perspective camera \"Back\" in the file; it has 0 \"Front\"",
                   pointer="/scene/camera/gltf")
    assert_problem(server.post("/api/jobs", json=gltf_job(asset["id"],
                                                          materials={"Red": {"metallic": 1}})),
                   422, detail="no material of that name in the file; its materials: Blue",
                   pointer="/scene/materials/Red")
    obj = stored(server, TRIANGLE_OBJ, OBJ)
    assert_problem(server.post("/api/jobs", json=gltf_job(obj["id"])), 422,
                   detail="is obj, not a glTF model (.glb, or .zip of a .gltf)", pointer="/scene/gltf/asset")
    forged = gltf_job(asset["id"])
    forged["scene"]["gltf"]["summary"] = {}
    assert_problem(server.post("/api/jobs", json=forged), 422,
                   detail="is written by the service", pointer="/scene/gltf/summary")
    # A required extension the renderer does not read: refused at upload, naming it.
    required = glb_bytes(glb_document(extensionsUsed=["KHR_draco_mesh_compression_x"],
                                      extensionsRequired=["KHR_draco_mesh_compression_x"]))
    r = upload(server, required, GLB)
    assert_problem(r, 422, detail="requires the extension \"KHR_draco_mesh_compression_x\"")
    # A material factor out of range, named.
    bad = glb_bytes(glb_document(
        materials=[{"name": "Hot", "pbrMetallicRoughness": {"metallicFactor": 2}}],
        meshes=[{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}]))
    assert_problem(upload(server, bad, GLB), 422,
                   detail="material 0 (Hot): pbrMetallicRoughness: metallicFactor is 2, not in "
                          "[0, 1]")
    server.healthy()


# A .gltf with its buffer and an image as files, zipped (application/zip).
ZIP = "application/zip"


def gltf_zip(entries=None, gltf_name="model/scene.gltf", uri="quad.bin", extra=None):
    """A zip of a .gltf (the quad with a base colour texture) and its files; `entries` replaces
    the files, `extra` adds (name, bytes) pairs."""
    bin_ = b"".join(struct.pack("<3f", *p) for p in QUAD_POSITIONS)
    bin_ += struct.pack(f"<{len(QUAD_INDICES)}H", *QUAD_INDICES)
    doc = glb_document(buffers=[{"byteLength": len(bin_), "uri": uri}],
                       images=[{"uri": "textures/tiles%20small.png"}],
                       textures=[{"source": 0}],
                       materials=[{"name": "Tiles", "pbrMetallicRoughness": {
                           "baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
                       meshes=[{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1,
                                                "material": 0}]}])
    with open(f"{ROOT}/assets/meshes/tiles.png", "rb") as f:
        png = f.read()
    files = entries if entries is not None else [
        (gltf_name, json.dumps(doc).encode()), ("model/quad.bin", bin_),
        ("model/textures/tiles small.png", png)]
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in files + list(extra or []):
            z.writestr(zipfile.ZipInfo(name), data, zipfile.ZIP_DEFLATED)
    return out.getvalue()


def test_a_zipped_gltf_uploads_and_renders(server):
    asset = stored(server, gltf_zip(), ZIP)
    assert asset["format"] == "zip"
    model = server.get(f"/api/assets/{asset['id']}").json()["model"]
    assert model["triangles"] == 4 and model["materials"] == ["Tiles"]
    assert model["textures"][0]["width"] > 0
    job = submit_ok(server, gltf_job(asset["id"], camera={"auto": {}, "width": 32}))
    assert run_to_end(server, job["id"])["state"] == "succeeded"


def test_hostile_zips_are_refused(server):
    cases = [
        (gltf_zip(uri="../quad.bin"), "leaves the .gltf's folder"),
        (gltf_zip(uri="/etc/passwd"), "leaves the .gltf's folder"),
        (gltf_zip(extra=[("../x", b"evil")]), "entry \"../x\": a name must stay inside the archive"),
        (gltf_zip(extra=[("/abs/x", b"evil")]), "entry \"/abs/x\": a name must stay inside"),
        (gltf_zip(extra=[("other.gltf", b"{}")]), "holds more than one .gltf"),
        (gltf_zip(entries=[("a.bin", b"x")]), "holds no .gltf file"),
        # A zip bomb: 64 MiB of zeros deflate to about 64 kB.
        (gltf_zip(extra=[("model/zeros.bin", bytes(64 << 20))]), "(a zip bomb?)"),
        (b"PK\x03\x04 not really a zip", "not a zip archive"),
        # A .glb sent as a zip: not one (or, when stored before as a .glb, refused as such).
        (QUAD_GLB + b"\0" * 4, "not a zip archive"),
    ]
    for body, detail in cases:
        assert_problem(upload(server, body, ZIP), 422, detail=detail)
    server.healthy()


def png_header(width, height):
    """A PNG whose header says width x height, with an empty zlib stream of pixel data."""
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(b"")) + chunk(b"IEND", b""))


def glb_with_bin(doc, bin_):
    """A .glb of the document and the BIN chunk `bin_` (padded)."""
    json_chunk = json.dumps(doc).encode()
    json_chunk += b" " * (-len(json_chunk) % 4)
    bin_ += b"\0" * (-len(bin_) % 4)
    body = (struct.pack("<II", len(json_chunk), 0x4E4F534A) + json_chunk +
            struct.pack("<II", len(bin_), 0x004E4942) + bin_)
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def test_hostile_glb_files_are_422_naming_the_object(server):
    """The issue's hostile files, through the service: each a 422 naming the glTF object, and the
    service answers after them."""
    quad = b"".join(struct.pack("<3f", *p) for p in QUAD_POSITIONS)
    quad += struct.pack(f"<{len(QUAD_INDICES)}H", *QUAD_INDICES)
    png = png_header(65535, 65535)
    huge = glb_document(
        images=[{"bufferView": 2, "mimeType": "image/png", "name": "huge"}],
        textures=[{"source": 0}],
        materials=[{"name": "Huge", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        meshes=[{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        bufferViews=glb_document()["bufferViews"] + [
            {"buffer": 0, "byteOffset": len(quad), "byteLength": len(png)}],
        buffers=[{"byteLength": len(quad) + len(png)}])
    cycle = glb_document(nodes=[{"mesh": 0, "children": [(i + 1) % 100]} for i in range(100)],
                         scenes=[{"nodes": []}])
    overflow = glb_document()
    overflow["accessors"][0]["count"] = 1 << 62
    out_of_range = glb_document()
    out_of_range["bufferViews"][0]["byteLength"] = 4096
    cases = [
        (glb_with_bin(huge, quad + png), "image 0 (huge): "),
        (glb_with_bin(huge, quad + png), "65535 x 65535 pixels, over the limit"),
        (glb_bytes(cycle), "node 0: its own ancestor (the node hierarchy has a cycle)"),
        (glb_bytes(overflow), "accessor 0: "),
        (glb_bytes(out_of_range), "bufferView 0: 4096 bytes at offset 0 run past the end"),
        (b"glTF\x02\x00\x00\x00garbage", "truncated"),
    ]
    for data, detail in cases:
        assert_problem(upload(server, data, GLB), 422, detail=detail)
    server.healthy()
