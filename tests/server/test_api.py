"""Integration tests of the HTTP API (docs/http-api.md; DESIGN.md, "Service") against
the real `caustic serve`: the read-only resources (/healthz, /api/openapi.json, /api/scenes and
/api/scenes/{name}, /api/settings, /metrics), submitting by example name and as a scene object,
Server-Sent Events to the end, the images, validation errors, and listing with paging and the state
filter.
test_job_control.py has cancel, delete, the preview, Idempotency-Key and the 404s."""

import json
import os
import re
import subprocess
import tempfile

import pytest

from conftest import (ID, ROOT, TINY_SCENE, assert_problem, exr_info, png_info, run_to_end,
                      sse_events, submit_ok, tiny_job, tiny_scene)


def test_a_second_server_on_a_port_in_use_does_not_start(server, caustic_bin):
    # cpp-httplib's default SO_REUSEPORT let it start and take a share of the first's connections.
    with tempfile.TemporaryDirectory() as data:
        second = subprocess.run([caustic_bin, "serve", "--port", str(server.port), "--data", data],
                                capture_output=True, text=True, timeout=30)
    assert second.returncode == 1, second
    assert f"cannot listen on 127.0.0.1:{server.port}" in second.stderr, second.stderr
    server.healthy()


# The read-only resources.

def test_healthz(server):
    r = server.get("/healthz")
    assert r.status_code == 200
    assert r.headers["Content-Type"].startswith("application/json")
    assert r.json() == {"status": "ok"}


def test_openapi_document_is_the_source_file(server):
    r = server.get("/api/openapi.json")
    assert r.status_code == 200
    assert r.headers["Content-Type"].startswith("application/json")
    with open(os.path.join(ROOT, "server", "http", "openapi.json"), encoding="utf-8") as f:
        assert r.json() == json.load(f)


def test_scene_format_is_served_where_the_openapi_document_links(server):
    # The API's externalDocs and its scene schema point at the scene format, served from docs/.
    document = server.get("/api/openapi.json").json()
    links = {document["externalDocs"]["url"]}
    for variant in document["components"]["schemas"]["JobRequest"]["properties"]["scene"]["oneOf"]:
        if "externalDocs" in variant:
            links.add(variant["externalDocs"]["url"])
    assert links == {"/docs/scene-format.md"}
    r = server.get("/docs/scene-format.md")
    assert r.status_code == 200
    assert r.headers["Content-Type"] == "text/markdown; charset=utf-8"
    with open(os.path.join(ROOT, "docs", "scene-format.md"), encoding="utf-8") as f:
        assert r.text == f.read()


def test_scene_format_example_with_an_uploaded_mesh_renders(server):
    # docs/scene-format.md's uploaded-mesh example as a user follows it: upload the teapot, put its
    # id where the example says ASSET_ID, render (tests/cli/docs_examples_test.cpp renders the rest).
    with open(os.path.join(ROOT, "assets", "meshes", "teapot.obj"), "rb") as f:
        r = server.post("/api/assets?name=teapot.obj", data=f.read(),
                        headers={"Content-Type": "model/obj"})
    assert r.status_code in (200, 201), r.text
    with open(os.path.join(ROOT, "docs", "scene-format.md"), encoding="utf-8") as f:
        blocks = re.findall(r"^```json\n(.*?)^```$", f.read(), re.S | re.M)
    examples = [b for b in blocks if '"ASSET_ID"' in b]
    assert len(examples) == 1
    scene = json.loads(examples[0].replace("ASSET_ID", r.json()["id"]))
    job = submit_ok(server, {"scene": scene, "settings": {"spp": 1}})
    assert run_to_end(server, job["id"])["state"] == "succeeded"


def test_scenes(server):
    r = server.get("/api/scenes")
    assert r.status_code == 200
    scenes = r.json()["scenes"]
    expected = sorted(n[:-5] for n in os.listdir(os.path.join(ROOT, "scenes"))
                      if n.endswith(".json"))
    assert scenes == expected
    assert {"cornell-box", "cornell-spheres", "bunny"} <= set(scenes)


def test_example_scene_by_name(server):
    # The file as written (the web page's scene editor starts from it); unknown names are 404.
    r = server.get("/api/scenes/cornell-box")
    assert r.status_code == 200 and r.headers["Content-Type"] == "application/json"
    with open(os.path.join(ROOT, "scenes", "cornell-box.json"), encoding="utf-8") as f:
        assert r.text == f.read()
    assert_problem(server.get("/api/scenes/no-such-scene"), 404, detail="no-such-scene")
    assert_problem(server.get("/api/scenes/..%2Fserver.log"), 404)


def test_settings(server):
    r = server.get("/api/settings")
    assert r.status_code == 200
    settings = r.json()
    for name in ("integrator", "spp", "time_limit", "photons", "seed", "threads", "exposure"):
        assert name in settings, name
    for name, s in settings.items():
        assert s["type"] in ("integer", "number", "string", "boolean"), (name, s)
        assert "default" in s and s["description"], (name, s)
        if s["type"] in ("integer", "number"):
            assert s["minimum"] <= s["default"] <= s["maximum"], (name, s)
        if "enum" in s:
            assert s["default"] in s["enum"], (name, s)
    assert settings["spp"]["minimum"] == 1
    assert "path" in settings["integrator"]["enum"]


def test_metrics(server):
    job = tiny_job(server, seed=101)
    assert run_to_end(server, job["id"])["state"] == "succeeded"
    r = server.get("/metrics")
    assert r.status_code == 200
    assert r.headers["Content-Type"].startswith("text/plain")
    values, types = {}, {}
    for line in r.text.splitlines():
        if line.startswith("# TYPE "):
            _, _, name, kind = line.split()
            types[name] = kind
        elif line and not line.startswith("#"):
            m = re.fullmatch(r'([a-z_]+(?:\{[a-z_]+="[a-z_]+"\})?) (\S+)', line)
            assert m, f"not a Prometheus sample: {line!r}"
            values[m.group(1)] = float(m.group(2))
    assert types["caustic_queue_depth"] == "gauge"
    assert types["caustic_rays_total"] == "counter"
    for state in ("queued", "running", "succeeded", "failed", "cancelled"):
        assert f'caustic_jobs{{state="{state}"}}' in values
    assert values['caustic_jobs{state="succeeded"}'] >= 1
    assert values["caustic_queue_depth"] == values['caustic_jobs{state="queued"}']
    assert values["caustic_rays_total"] > 0
    assert values["caustic_passes_total"] >= 4
    assert values["caustic_render_seconds_total"] > 0
    assert values["caustic_event_streams"] >= 0


# Submitting and rendering.

def test_submit_example_scene_by_name(server):
    job = submit_ok(server, {"scene": "cornell-box", "settings": {"spp": 1, "preset": "none"}})
    assert job["state"] == "queued"
    assert job["scene_name"] == "cornell-box"
    assert job["created_at"].endswith("Z") and job["finished_at"] is None
    # The stored settings are complete for the job's integrator: the general settings and every
    # one it reads (a path job lists no photon setting), the request's over the scene's own, and
    # the server's time limit for a job that sets none.
    settings = server.get("/api/settings").json()
    assert job["settings"]["integrator"] == "path"
    assert set(job["settings"]) == {name for name, s in settings.items()
                                    if (not s["integrators"] or "path" in s["integrators"])
                                    and "path" not in s.get("only_with", {})}
    assert "rr_depth" in job["settings"] and "photons" not in job["settings"]
    assert job["settings"]["spp"] == 1
    assert job["settings"]["time_limit"] == 3600
    assert job["links"]["cancel"] == f"/api/jobs/{job['id']}/cancel"

    end = run_to_end(server, job["id"])
    assert end["state"] == "succeeded", end
    assert end["progress"] == 1 and end["passes_done"] == end["passes_total"] == 1
    assert end["stats"]["spp"] == 1 and end["stats"]["rays"] > 0
    # The job's wall time: loading, setup, the pass and the images.
    assert end["stats"]["total_seconds"] >= end["stats"]["render_seconds"] > 0
    assert end["links"]["image_png"] == f"/api/jobs/{job['id']}/image.png"
    assert "cancel" not in end["links"]

    png = server.get(end["links"]["image_png"])
    assert png.status_code == 200 and png.headers["Content-Type"] == "image/png"
    assert "immutable" in png.headers["Cache-Control"]
    assert png_info(png.content) == (512, 512)
    exr = server.get(end["links"]["image_exr"])
    assert exr.status_code == 200 and exr.headers["Content-Type"] == "image/x-exr"
    width, height, channels = exr_info(exr.content)
    assert (width, height) == (512, 512)
    assert {"R", "G", "B"} <= set(channels)
    assert (job["settings"]["width"], job["settings"]["height"]) == (512, 512)


@pytest.mark.parametrize("asked, size", [({"width": 48}, (48, 48)),
                                         ({"height": 40}, (40, 40)),
                                         ({"width": 64, "height": 32}, (64, 32))])
def test_settings_resolution_overrides_the_camera(server, asked, size):
    # cornell-box's camera is 512 x 512: one side given keeps its aspect ratio.
    job = submit_ok(server, {"scene": "cornell-box", "settings": {"spp": 1, **asked}})
    assert (job["settings"]["width"], job["settings"]["height"]) == size
    end = run_to_end(server, job["id"])
    assert end["state"] == "succeeded", end
    assert png_info(server.get(end["links"]["image_png"]).content) == size
    assert exr_info(server.get(end["links"]["image_exr"]).content)[:2] == size


def test_settings_resolution_is_held_to_the_service_limits(server):
    # Each side at most --max-resolution (4096), the image at most --max-pixels (2048 x 2048).
    r = server.submit({"scene": "cornell-box", "settings": {"height": 5000}})
    assert_problem(r, 422, "/settings/height", "4096")
    r = server.submit({"scene": "cornell-box", "settings": {"width": 4096}})
    assert_problem(r, 422, "/settings/width", "pixels")
    r = server.submit({"scene": "cornell-box", "settings": {"width": -1}})
    assert_problem(r, 422, "/settings/width")


def test_submit_scene_object(server):
    job = submit_ok(server, {"scene": TINY_SCENE, "settings": {"spp": 4, "seed": 7}})
    assert job["scene_name"] is None
    assert job["settings"]["spp"] == 4 and job["settings"]["seed"] == 7
    events = sse_events(server, job["id"])
    kinds = [k for k, _ in events]
    assert kinds[-1] == "end" and set(kinds[:-1]) <= {"progress"}, kinds
    end = events[-1][1]
    assert end["state"] == "succeeded", end
    assert end["passes_done"] == 4 and end["progress"] == 1
    assert end["started_at"] <= end["finished_at"]
    # The job resource has the convergence log: one point a pass.
    full = server.job(job["id"])
    assert [p["pass"] for p in full["convergence"]] == [1, 2, 3, 4]
    assert all(p["seconds"] >= 0 for p in full["convergence"])
    assert full["relative_error"] is None or full["relative_error"] >= 0
    assert png_info(server.get(f"/api/jobs/{job['id']}/image.png").content) == (32, 32)
    assert exr_info(server.get(f"/api/jobs/{job['id']}/image.exr").content)[:2] == (32, 32)
    # The preview of a finished job is its result.
    preview = server.get(f"/api/jobs/{job['id']}/preview.png")
    assert preview.status_code == 200 and png_info(preview.content) == (32, 32)
    # A stream opened after the end has the one `end` event.
    again = sse_events(server, job["id"])
    assert [k for k, _ in again] == ["end"]


def test_request_settings_override_the_scenes(server):
    scene = tiny_scene()
    scene["settings"] = {"spp": 2, "max_depth": 3}
    job = submit_ok(server, {"scene": scene, "settings": {"spp": 3}})
    assert job["settings"]["spp"] == 3 and job["settings"]["max_depth"] == 3
    assert run_to_end(server, job["id"])["passes_done"] == 3


def test_auto_is_the_default_and_says_what_it_chose_and_why(server):
    # cornell-box: a closed diffuse room under a lamp, nothing specular: the indirect map alone.
    job = submit_ok(server, {"scene": "cornell-box", "settings": {"spp": 16}})
    assert job["settings"]["preset"] == "auto"
    assert job["settings"]["indirect"] == "photon_map" and job["settings"]["caustics"] == "paths"
    assert job["settings"]["sampler"] == "sobol_sequence"
    assert job["settings"]["spp_per_pass"] == 2  # 8 passes of the 16 spp asked
    assert "indirect_photons" in job["settings"]
    choice = job["preset_choice"]
    assert choice["preset"] == "auto"
    assert choice["settings"] == {"indirect": "photon_map"}
    assert [r.split(":")[0] for r in choice["reasons"]] == ["caustics", "indirect", "spp_per_pass"]
    assert "no mirror or smooth glass" in choice["reasons"][0]
    final = run_to_end(server, job["id"])
    assert final["state"] == "succeeded" and final["preset_choice"] == choice
    assert final["stats"]["relative_bias"] >= 0
    # Under a target error its passes follow the target (the preset's under_target), and it says
    # why: 4 a pass at 2% or more, 8 at 1% or more.
    under = server.get("/api/settings").json()["preset"]["presets"]["auto"]["under_target"]
    assert [(r["target_error"], r["settings"]) for r in under] == [
        (0.02, {"spp_per_pass": 4}), (0.01, {"spp_per_pass": 8})]
    for target, size in ((0.5, 4), (0.01, 8), (0.005, 16)):
        job = submit_ok(server, {"scene": "cornell-box",
                                 "settings": {"spp": 256, "target_error": target, "width": 8}})
        assert job["settings"]["spp_per_pass"] == size, target
        assert job["preset_choice"]["reasons"][2].startswith(f"spp_per_pass: {size}; a target")
        assert server.post(f"/api/jobs/{job['id']}/cancel").status_code == 202
        server.wait(job["id"], {"cancelled", "succeeded"})
    # A target that is no number is refused where it is, not taken by auto's choice.
    r = server.submit({"scene": "cornell-box", "settings": {"target_error": "1%"}})
    assert_problem(r, 422, "/settings/target_error", "expected a number, got a string")
    # A request's own value stands; preset none chooses nothing.
    job = submit_ok(server, {"scene": "cornell-box", "settings": {"spp": 16, "indirect": "paths"}})
    assert job["settings"]["indirect"] == "paths" and job["preset_choice"]["settings"] == {}
    assert "replaced by indirect=\"paths\"" in job["preset_choice"]["reasons"][1]
    job = submit_ok(server, {"scene": "cornell-box", "settings": {"spp": 16, "preset": "none"}})
    assert job["preset_choice"] is None and job["settings"]["sampler"] == "independent"


def test_a_preset_sits_between_the_scene_and_the_request(server):
    spec = server.get("/api/settings").json()["preset"]
    assert spec["enum"] == ["none", "auto", "draft", "preview", "final"]
    assert spec["default"] == "auto"
    presets = spec["presets"]
    assert set(presets) == {"auto", "draft", "preview", "final"}
    for p in presets.values():
        assert p["description"] and p["settings"]
    scene = tiny_scene()
    scene["settings"] = {"spp": 2, "max_depth": 3, "target_error": 0.5}
    # The preset replaces the scene's values for what it sets...
    job = submit_ok(server, {"scene": scene, "settings": {"preset": "draft"}})
    assert job["settings"]["preset"] == "draft"
    for key, value in presets["draft"]["settings"].items():
        assert job["settings"][key] == value, key
    assert job["settings"]["max_depth"] == 3  # not the draft's business
    # ... and what the request names replaces the preset's.
    job = submit_ok(server, {"scene": scene, "settings": {"preset": "draft", "spp": 3}})
    assert job["settings"]["spp"] == 3
    assert run_to_end(server, job["id"])["state"] == "succeeded"
    # An unknown preset is a 422 at its path, naming the valid ones.
    r = server.submit({"scene": scene, "settings": {"preset": "ultra"}})
    assert_problem(r, 422, "/settings/preset", "valid: none, auto, draft, preview, final")


def test_the_error_of_photon_mapping_includes_its_bias(server):
    # The photon mappers' films carry their bias (film/film.h): the error is noise plus bias, the
    # stats give both, and error_excludes_bias (kept for clients) is false for every job.
    for extra, mapped in (({"integrator": "path"}, False), ({"integrator": "photon"}, True),
                          ({"integrator": "ppm"}, True),
                          ({"integrator": "path", "caustics": "photon_map"}, True)):
        job = submit_ok(server, {"scene": TINY_SCENE,
                                 "settings": {**extra, "spp": 4, "spp_per_pass": 1,
                                              "photons": 1000}})
        assert job["error_excludes_bias"] is False, extra
        done = run_to_end(server, job["id"])
        assert done["error_excludes_bias"] is False and done["eta_reason"] is None, done
        stats = done["stats"]
        error, noise, bias = stats["relative_error"], stats["relative_noise"], stats["relative_bias"]
        assert abs(error ** 2 - noise ** 2 - bias ** 2) <= 1e-9 * max(error ** 2, 1e-30), stats
        if not mapped:
            assert bias == 0, (extra, stats)


def test_invalid_submissions_name_the_json_path(server):
    # The error cases: malformed JSON (400), invalid scene or settings or over a limit
    # (422 with the JSON path), a body over the limit (413, test_bad_input.py), unknown job (404),
    # an unfinished job's image and a reused Idempotency-Key (409, below).
    assert_problem(server.submit('{"scene": '), 400)
    assert_problem(server.submit({"scene": "no-such-scene"}), 422, "/scene")
    assert_problem(server.submit({"scene": tiny_scene(width=0)}), 422, "/scene/camera/width")
    assert_problem(server.submit({"scene": TINY_SCENE, "settings": {"spp": 0}}), 422,
                   "/settings/spp")
    assert_problem(server.submit({"scene": TINY_SCENE, "settings": {"spp": 1 << 20}}), 422,
                   "/settings/spp")
    assert_problem(server.submit({"scene": TINY_SCENE, "settings": {"time_limit": 7200}}), 422,
                   "/settings/time_limit", "at most 3600")
    scene = tiny_scene()
    scene["shapes"][1]["material"] = "nope"
    assert_problem(server.submit({"scene": scene}), 422, "/scene/shapes/1/material")
    scene = tiny_scene()
    scene["settings"] = {"integrator": "nope"}
    assert_problem(server.submit({"scene": scene}), 422, "/scene/settings/integrator")


# Listing.

def test_list_pages_newest_first(server):
    ids = [tiny_job(server, seed=200 + i, spp=1)["id"] for i in range(5)]
    for i in ids:
        server.wait(i, {"succeeded"})
    seen, cursor, pages = [], None, 0
    while True:
        params = {"limit": 2}
        if cursor is not None:
            params["cursor"] = cursor
        r = server.get("/api/jobs", params=params)
        assert r.status_code == 200, r.text
        page = r.json()
        assert set(page) == {"jobs", "next_cursor"}
        assert len(page["jobs"]) <= 2
        for j in page["jobs"]:
            assert "convergence" not in j  # the list stays small
            assert ID.match(j["id"]) and j["links"]["self"] == f"/api/jobs/{j['id']}"
        seen += [j["id"] for j in page["jobs"]]
        pages += 1
        cursor = page["next_cursor"]
        if cursor is None:
            break
        assert isinstance(cursor, int) and len(page["jobs"]) == 2
        assert pages < 1000
    assert len(seen) == len(set(seen)), "a job on two pages"
    # Newest first: the five, in reverse submission order, at the head of the list.
    assert seen[:5] == ids[::-1]
    default = server.get("/api/jobs").json()
    assert len(default["jobs"]) == min(20, len(seen))
    everything = server.get("/api/jobs", params={"limit": 100}).json()
    assert [j["id"] for j in everything["jobs"]] == seen[:100]


def test_list_state_filter(server, long_job):
    queued = tiny_job(server, seed=300)["id"]
    cancelled = tiny_job(server, seed=301)["id"]
    assert server.post(f"/api/jobs/{cancelled}/cancel").status_code == 202
    for state, must in (("running", long_job), ("queued", queued), ("cancelled", cancelled)):
        r = server.get("/api/jobs", params={"state": state, "limit": 100})
        assert r.status_code == 200, r.text
        jobs = r.json()["jobs"]
        assert jobs and all(j["state"] == state for j in jobs), (state, jobs)
        assert must in [j["id"] for j in jobs], state
    succeeded = server.get("/api/jobs", params={"state": "succeeded", "limit": 100}).json()
    assert all(j["state"] == "succeeded" for j in succeeded["jobs"])
    assert queued not in [j["id"] for j in succeeded["jobs"]]
    failed = server.get("/api/jobs", params={"state": "failed"}).json()
    assert failed == {"jobs": [], "next_cursor": None}
