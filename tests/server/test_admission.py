"""Lean admission (DESIGN.md, "Service"): POST /api/jobs validates and estimates memory from counts,
reading each mesh file's counts once and parsing no mesh; the worker's render checks again from
what it builds, and a job whose estimate was wrong ends failed with the problem's JSON path and
detail. Each test runs its own server on a temporary assets folder it can change."""

import json
import re

from conftest import TINY_SCENE, assert_problem, submit_ok

END_STATES = {"succeeded", "failed", "cancelled"}


def mesh_scene(file):
    """TINY_SCENE with a mesh of `file` as its second shape (/scene/shapes/1)."""
    scene = json.loads(json.dumps(TINY_SCENE))
    scene["shapes"].insert(1, {"type": "mesh", "file": file, "material": "white"})
    return scene


def write_grid(path, triangles):
    """A flat grid of about `triangles` triangles in the unit square (2 a cell)."""
    cols = max(1, int((triangles / 2) ** 0.5))
    rows = max(1, triangles // (2 * cols))
    with open(path, "w") as f:
        for j in range(rows + 1):
            f.write("".join(f"v {i / cols} {j / rows} -0.5\n" for i in range(cols + 1)))
        for j in range(rows):
            for i in range(cols):
                a = j * (cols + 1) + i + 1
                f.write(f"f {a} {a + 1} {a + cols + 1}\nf {a + 1} {a + cols + 2} {a + cols + 1}\n")


def mesh_scans(server):
    m = re.search(r"^caustic_mesh_scans_total (\S+)$", server.get("/metrics").text, re.M)
    assert m, "no caustic_mesh_scans_total in /metrics"
    return float(m.group(1))


def test_admission_counts_a_mesh_once_and_never_parses_it(start_server, tmp_path):
    # The third vertex overflows a float: loading the mesh refuses it, counting it cannot tell.
    assets = tmp_path / "assets"
    assets.mkdir()
    (assets / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n")
    server = start_server("--threads", "2", "--assets", str(assets))
    body = {"scene": mesh_scene("bad.obj"), "settings": {"spp": 1}}
    assert mesh_scans(server) == 0
    job = submit_ok(server, body)
    assert mesh_scans(server) == 1
    again = submit_ok(server, body)
    assert mesh_scans(server) == 1  # the same file, unchanged: not read again
    # The worker loads the mesh and fails the job with the load's path and detail.
    for j in (job, again):
        final = server.wait(j["id"], END_STATES)
        assert final["state"] == "failed", final
        # The worker names the path within the scene (/shapes/1/file) where a 422 names it
        # within the body (/scene/shapes/1/file).
        assert final["error"].endswith("/shapes/1/file: vertex 3 of bad.obj is not finite"), final
    server.healthy()


def test_a_job_whose_exact_check_fails_ends_failed_with_the_problem(start_server, tmp_path):
    assets = tmp_path / "assets"
    assets.mkdir()
    mesh = assets / "mesh.obj"
    write_grid(mesh, 2)
    server = start_server("--threads", "2", "--assets", str(assets))
    # The one worker renders a long job while ours waits in the queue.
    blocker = submit_ok(server, {"scene": "cornell-box",
                                 "settings": {"spp": 4096, "spp_per_pass": 1, "time_limit": 120}})
    server.wait(blocker["id"], {"running"})
    body = {"scene": mesh_scene("mesh.obj"), "settings": {"spp": 1, "memory_limit": 8}}
    job = submit_ok(server, body)  # two triangles and a 32² film: well under 8 MiB
    # The mesh grows to 200000 triangles (some 20 MiB with its accelerator) after admission.
    write_grid(mesh, 200000)
    assert server.post(f"/api/jobs/{blocker['id']}/cancel").status_code == 202
    final = server.wait(job["id"], END_STATES, deadline=90)
    assert final["state"] == "failed", final
    path, _, detail = final["error"].partition(": ")
    assert path == "/settings/memory_limit", final
    assert detail.startswith("the scene, its accelerator and the film already take "), final
    assert detail.endswith("MiB, more than the limit of 8 MiB"), final
    # Submitted now, the job is refused at once with the same path: the changed file is counted
    # again, and the estimate from its counts says the same.
    problem = assert_problem(server.submit(body), 422, "/settings/memory_limit",
                             detail="more than the limit of 8 MiB")
    assert problem["detail"].startswith("/settings/memory_limit: the scene, its accelerator and "
                                        "the film would take about "), problem
    server.healthy()
