"""The hostile requests of test_bad_input.py, one Case each: what is sent, the expected status and
problem `pointer` (the JSON path at fault; None where there is none), and which server gets it."""

import gzip
import json
import zlib
from dataclasses import dataclass, field

from conftest import TINY_SCENE, tiny_scene

MAX_REQUEST_BYTES = 1 << 20
TOKEN = "s3cret-token-for-tests"
UNKNOWN_ID = "0123456789abcdef0123456789abcdef"
NO_BODY = object()

TRIANGLE_OBJ = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n"


def scene_with(**fields):
    scene = tiny_scene()
    scene.update(fields)
    return scene


def with_camera(**camera):
    return {"scene": tiny_scene(**camera), "settings": {"spp": 1}}


def with_shape(shape):
    return {"scene": scene_with(shapes=[shape]), "settings": {"spp": 1}}


def with_mesh(file):
    return with_shape({"type": "mesh", "file": file, "material": "white"})


def with_settings(**settings):
    return {"scene": TINY_SCENE, "settings": settings}


@dataclass
class Case:
    name: str
    status: int
    pointer: str = None  # the problem's JSON path; None: the problem has none
    body: object = NO_BODY  # JSON value, or str/bytes sent as they are
    method: str = "POST"
    path: str = "/api/jobs"
    headers: dict = field(default_factory=dict)
    raw: bytes = None  # the whole request, sent byte for byte
    server: str = "main"
    detail: str = None  # a part of the problem's detail


def get_as_is(path):
    return f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n".encode("latin-1")


CASES = [
    # Malformed JSON: 400, no pointer.
    Case("deep_array_nesting_100000", 400, body="[" * 100000, detail="nested deeper"),
    Case("deep_object_nesting_100000", 400, body='{"a":' * 100000, detail="nested deeper"),
    Case("deep_but_well_formed_scene_70", 400, body='{"scene":' + "[" * 70 + "]" * 70 + "}",
         detail="nested deeper"),
    Case("nan_literal", 400, body='{"scene":"cornell-box","settings":{"spp":NaN}}'),
    Case("infinity_literal", 400, body='{"scene":"cornell-box","settings":{"spp":Infinity}}'),
    Case("minus_infinity_literal", 400,
         body='{"scene":"cornell-box","settings":{"exposure":-Infinity}}'),
    Case("number_1e400_overflows", 400, body='{"scene":"cornell-box","settings":{"spp":1e400}}'),
    Case("number_minus_1e400_overflows", 400,
         body='{"scene":"cornell-box","settings":{"exposure":-1e400}}'),
    Case("hex_number", 400, body='{"scene":"cornell-box","settings":{"spp":0x10}}'),
    Case("empty_body", 400, body=""),
    Case("truncated_json", 400, body='{"scene": "cornell-box"'),
    Case("trailing_garbage", 400, body='{"scene":"cornell-box"} x'),
    Case("nul_byte_then_garbage", 400, body=b'{"scene":"cornell-box"}\x00{{{', detail="NUL"),
    Case("invalid_utf8_in_string", 400, body=b'{"scene":"\xff\xfe"}'),
    Case("lone_utf16_surrogate", 400, body='{"scene":"\\ud800"}'),
    Case("raw_control_character_in_string", 400, body='{"scene":"a\x01b"}'),
    Case("single_quotes", 400, body="{'scene':'cornell-box'}"),
    Case("comment", 400, body='{"scene":"cornell-box" /* hi */}'),
    # The body's shape: 422 naming the path.
    Case("body_is_array", 422, "/", body=[]),
    Case("body_is_null", 422, "/", body=None),
    Case("body_is_number", 422, "/", body=42),
    Case("body_is_string", 422, "/", body='"cornell-box"'),
    Case("scene_missing", 422, "/scene", body={"settings": {"spp": 1}}),
    Case("scene_is_null", 422, "/scene", body={"scene": None}),
    Case("scene_is_number", 422, "/scene", body={"scene": 5}),
    Case("scene_is_array", 422, "/scene", body={"scene": [TINY_SCENE]}),
    Case("unknown_top_level_field", 422, "/owner", body={"scene": "cornell-box", "owner": "me"}),
    Case("priority_is_string", 422, "/priority", body={"scene": "cornell-box", "priority": "high"}),
    Case("priority_out_of_range", 422, "/priority", body={"scene": "cornell-box", "priority": 1001}),
    Case("priority_fractional", 422, "/priority", body={"scene": "cornell-box", "priority": 1.5}),
    Case("task_passes_zero", 422, "/task_passes", body={"scene": "cornell-box", "task_passes": 0}),
    Case("example_name_path_traversal", 422, "/scene", body={"scene": "../../etc/passwd"}),
    Case("example_name_absolute_path", 422, "/scene", body={"scene": "/etc/passwd"}),
    Case("example_name_with_nul", 422, "/scene", body={"scene": "cornell-box\u0000"}),
    Case("settings_is_array", 422, "/settings", body={"scene": "cornell-box", "settings": []}),
    Case("settings_is_string", 422, "/settings", body={"scene": "cornell-box", "settings": "fast"}),
    # Unknown fields, anywhere.
    Case("unknown_setting", 422, "/settings/turbo", body=with_settings(turbo=True)),
    Case("unknown_field_in_scene", 422, "/scene/owner", body={"scene": scene_with(owner="x")}),
    Case("unknown_field_in_camera", 422, "/scene/camera/zoom", body=with_camera(zoom=2)),
    Case("unknown_field_in_shape", 422, "/scene/shapes/0/color",
         body=with_shape({**TINY_SCENE["shapes"][0], "color": [1, 0, 0]})),
    Case("unknown_field_in_material", 422, "/scene/materials/white/shine",
         body={"scene": scene_with(materials={**TINY_SCENE["materials"],
                                              "white": {"type": "diffuse", "shine": 1}})}),
    Case("unknown_setting_in_scene", 422, "/scene/settings/bogus",
         body={"scene": scene_with(settings={"bogus": 1})}),
    # Wrong types and numbers out of range in the settings.
    Case("spp_string", 422, "/settings/spp", body=with_settings(spp="4")),
    Case("spp_fraction", 422, "/settings/spp", body=with_settings(spp=1.5)),
    Case("spp_boolean", 422, "/settings/spp", body=with_settings(spp=True)),
    Case("spp_null", 422, "/settings/spp", body=with_settings(spp=None)),
    Case("spp_1e308", 422, "/settings/spp", body=with_settings(spp=1e308)),
    Case("spp_negative", 422, "/settings/spp", body=with_settings(spp=-1)),
    Case("spp_zero", 422, "/settings/spp", body=with_settings(spp=0)),
    Case("spp_over_server_limit", 422, "/settings/spp", body=with_settings(spp=100000),
         detail="on this server"),
    Case("spp_over_range", 422, "/settings/spp", body=with_settings(spp=10 ** 7)),
    Case("photons_1e12", 422, "/settings/photons",
         body=with_settings(integrator="photon", photons=1e12)),
    Case("photons_over_server_limit", 422, "/settings/photons",
         body=with_settings(integrator="photon", photons=20000000), detail="on this server"),
    Case("caustic_photons_over_server_limit", 422, "/settings/caustic_photons",
         body=with_settings(integrator="photon", caustic_photons=20000000)),
    Case("time_limit_negative", 422, "/settings/time_limit", body=with_settings(time_limit=-1)),
    Case("time_limit_over_server_limit", 422, "/settings/time_limit",
         body=with_settings(time_limit=1e5), detail="on this server"),
    Case("memory_limit_over_server_limit", 422, "/settings/memory_limit",
         body=with_settings(memory_limit=1e6)),
    Case("seed_2_to_the_64", 422, "/settings/seed", body=with_settings(seed=2 ** 64)),
    Case("seed_negative", 422, "/settings/seed", body=with_settings(seed=-1)),
    Case("integrator_unknown", 422, "/settings/integrator", body=with_settings(integrator="magic")),
    Case("boolean_as_string", 422, "/settings/light_sampling",
         body=with_settings(light_sampling="true")),
    Case("exposure_1e308", 422, "/settings/exposure", body=with_settings(exposure=1e308)),
    Case("rr_depth_1e15", 422, "/settings/rr_depth", body=with_settings(rr_depth=10 ** 15)),
    # Image sizes and scene numbers.
    Case("image_100000_by_100000", 422, "/scene/camera/width",
         body=with_camera(width=100000, height=100000)),
    Case("width_negative", 422, "/scene/camera/width", body=with_camera(width=-32)),
    Case("height_zero", 422, "/scene/camera/height", body=with_camera(height=0)),
    Case("width_string", 422, "/scene/camera/width", body=with_camera(width="32")),
    Case("width_fraction", 422, "/scene/camera/width", body=with_camera(width=32.5)),
    Case("width_1e308", 422, "/scene/camera/width", body=with_camera(width=1e308)),
    Case("pixels_over_limit_4096_by_4096", 422, "/scene/camera/width",
         body=with_camera(width=4096, height=4096), detail="pixels"),
    Case("fov_zero", 422, "/scene/camera/fov", body=with_camera(fov=0)),
    Case("look_at_1e308", 422, "/scene/camera/look_at/0", body=with_camera(look_at=[1e308, 0, 0])),
    Case("position_huge_array", 422, "/scene/camera/position",
         body='{"scene":{"camera":{"position":[' + ",".join(["0"] * 300000) + "]}}}"),
    Case("shapes_huge_array", 422, "/scene/shapes/0",
         body='{"scene":{"camera":' + json.dumps(TINY_SCENE["camera"]) + ',"materials":'
         + json.dumps(TINY_SCENE["materials"]) + ',"shapes":[' + ",".join(["1"] * 300000)
         + "]}}"),
    Case("radius_negative", 422, "/scene/shapes/0/radius",
         body=with_shape({**TINY_SCENE["shapes"][0], "radius": -1})),
    Case("radius_1e308", 422, "/scene/shapes/0/radius",
         body=with_shape({**TINY_SCENE["shapes"][0], "radius": 1e308})),
    Case("emission_1e308", 422, "/scene/materials/lamp/emission/0",
         body={"scene": scene_with(materials={**TINY_SCENE["materials"], "lamp": {
             "type": "diffuse", "emission": [1e308, 1, 1]}})}),
    Case("albedo_over_1", 422, "/scene/materials/white/albedo/1",
         body={"scene": scene_with(materials={**TINY_SCENE["materials"], "white": {
             "type": "diffuse", "albedo": [0.5, 2, 0.5]}})}),
    Case("unknown_material", 422, "/scene/shapes/0/material",
         body=with_shape({**TINY_SCENE["shapes"][0], "material": "gold"})),
    # Mesh files outside the assets folder.
    Case("mesh_dotdot_etc_passwd", 422, "/scene/shapes/0/file", body=with_mesh("../../etc/passwd")),
    Case("mesh_dotdot_after_a_folder", 422, "/scene/shapes/0/file",
         body=with_mesh("sub/../../outside.obj")),
    Case("mesh_absolute_path", 422, "/scene/shapes/0/file", body=with_mesh("/etc/passwd")),
    Case("mesh_symlink_to_etc_passwd", 422, "/scene/shapes/0/file",
         body=with_mesh("passwd-link.obj"), detail="must not leave"),
    Case("mesh_symlink_to_an_obj_outside", 422, "/scene/shapes/0/file",
         body=with_mesh("outside-link.obj"), detail="must not leave"),
    Case("mesh_through_a_symlinked_folder", 422, "/scene/shapes/0/file",
         body=with_mesh("etc-link/passwd"), detail="must not leave"),
    Case("mesh_percent_encoded_dotdot", 422, "/scene/shapes/0/file",
         body=with_mesh("%2e%2e/%2e%2e/etc/passwd")),
    Case("mesh_backslashes", 422, "/scene/shapes/0/file", body=with_mesh("..\\..\\etc\\passwd")),
    Case("mesh_nul_byte", 422, "/scene/shapes/0/file", body=with_mesh("tiny.obj\u0000.png")),
    Case("mesh_a_folder", 422, "/scene/shapes/0/file", body=with_mesh("sub")),
    Case("mesh_empty_name", 422, "/scene/shapes/0/file", body=with_mesh("")),
    Case("mesh_name_not_a_string", 422, "/scene/shapes/0/file", body=with_mesh(5)),
    # Static URLs that try to leave web/.
    Case("static_dotdot", 404, raw=get_as_is("/../../etc/passwd")),
    Case("static_encoded_dots", 404, raw=get_as_is("/%2e%2e/%2e%2e/etc/passwd")),
    Case("static_encoded_slashes", 404, raw=get_as_is("/..%2f..%2fetc%2fpasswd")),
    Case("static_all_encoded", 404, raw=get_as_is("/%2e%2e%2f%2e%2e%2fetc%2fpasswd")),
    Case("static_double_encoded", 404, raw=get_as_is("/%252e%252e/%252e%252e/etc/passwd")),
    Case("static_mixed_dots", 404, raw=get_as_is("/.%2e/.%2e/.%2e/etc/passwd")),
    Case("static_double_slash", 404, raw=get_as_is("//etc/passwd")),
    Case("static_below_a_file", 404, raw=get_as_is("/index.html/../../../etc/passwd")),
    Case("static_backslashes", 404, raw=get_as_is("/..\\..\\etc\\passwd")),
    Case("static_nul_byte", 400, raw=get_as_is("/index.html%00.png"), detail="NUL"),
    Case("api_dotdot", 404, raw=get_as_is("/api/jobs/../../../../etc/passwd")),
    # ... and docs/ (served at /docs/).
    Case("docs_dotdot", 404, raw=get_as_is("/docs/../../../etc/passwd")),
    Case("docs_encoded_dots", 404, raw=get_as_is("/docs/%2e%2e/README.md")),
    # Job ids.
    Case("id_31_hex", 404, method="GET", path="/api/jobs/" + UNKNOWN_ID[:31]),
    Case("id_33_hex", 404, method="GET", path="/api/jobs/" + UNKNOWN_ID + "0"),
    Case("id_upper_case", 404, method="GET", path="/api/jobs/" + UNKNOWN_ID.upper()),
    Case("id_unknown", 404, method="GET", path="/api/jobs/" + UNKNOWN_ID, detail="no job"),
    Case("id_sql", 404, method="GET", path="/api/jobs/%27%3B%20DROP%20TABLE%20jobs%3B--"),
    Case("id_nul", 400, method="GET", path=f"/api/jobs/{UNKNOWN_ID}%00"),
    Case("delete_bad_id", 404, method="DELETE", path="/api/jobs/" + "g" * 32),
    Case("cancel_unknown_id", 404, path=f"/api/jobs/{UNKNOWN_ID}/cancel"),
    Case("image_of_dotdot_id", 404, raw=get_as_is("/api/jobs/../image.png")),
    # Query parameters.
    Case("limit_zero", 400, method="GET", path="/api/jobs?limit=0"),
    Case("limit_101", 400, method="GET", path="/api/jobs?limit=101"),
    Case("limit_negative", 400, method="GET", path="/api/jobs?limit=-1"),
    Case("limit_text", 400, method="GET", path="/api/jobs?limit=abc"),
    Case("limit_exponent", 400, method="GET", path="/api/jobs?limit=1e2"),
    Case("limit_huge", 400, method="GET", path="/api/jobs?limit=99999999999999999999"),
    Case("cursor_zero", 400, method="GET", path="/api/jobs?cursor=0"),
    Case("cursor_negative", 400, method="GET", path="/api/jobs?cursor=-5"),
    Case("cursor_text", 400, method="GET", path="/api/jobs?cursor=%27%20OR%201%3D1"),
    Case("cursor_huge", 400, method="GET", path="/api/jobs?cursor=99999999999999999999"),
    Case("state_unknown", 400, method="GET", path="/api/jobs?state=bogus"),
    Case("state_upper_case", 400, method="GET", path="/api/jobs?state=SUCCEEDED"),
    Case("state_empty", 400, method="GET", path="/api/jobs?state="),
    # Headers, sizes and HTTP itself.
    Case("idempotency_key_over_200", 400, body={"scene": "cornell-box"},
         headers={"Idempotency-Key": "k" * 201}),
    Case("header_of_20000_bytes", 400, method="GET", path="/healthz",
         headers={"X-Big": "a" * 20000}),
    Case("url_of_20000_bytes", 414, method="GET", path="/api/jobs?state=" + "a" * 20000),
    Case("body_over_the_limit", 413, body='{"scene":"' + "a" * (MAX_REQUEST_BYTES + 1) + '"}'),
    # Only a Content-Length holds a body to the limit: chunked and compressed bodies are refused.
    Case("chunked_body_over_the_limit", 411,
         body=iter([b'{"scene":"'] + [b"a" * 65536] * 20 + [b'"}'])),
    Case("chunked_small_body", 411, body=iter([b'{"scene":', b'"cornell-box"}'])),
    Case("gzip_bomb", 415, body=gzip.compress(b'{"scene":"' + b"a" * (8 * MAX_REQUEST_BYTES)
                                              + b'"}'), headers={"Content-Encoding": "gzip"}),
    Case("deflate_body", 415, body=zlib.compress(b'{"scene":"cornell-box"}'),
         headers={"Content-Encoding": "deflate"}),
    Case("post_without_content_length", 400, raw=b"POST /api/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\n"
         b"Connection: close\r\n\r\n{\"scene\":\"cornell-box\"}", detail="malformed JSON"),
    Case("garbage_request_line", 400, raw=b"\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03\r\n\r\n"),
    Case("bad_chunk_size", 411, raw=b"POST /api/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\n"
         b"Connection: close\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\nabc\r\n0\r\n\r\n"),
    # Bearer tokens (a server with --token): POST and DELETE need it.
    Case("token_missing_on_submit", 401, server="token", body={"scene": "cornell-box"}),
    Case("token_wrong_on_submit", 401, server="token", body={"scene": "cornell-box"},
         headers={"Authorization": "Bearer wrong"}),
    Case("token_prefix_only", 401, server="token", body={"scene": "cornell-box"},
         headers={"Authorization": "Bearer " + TOKEN[:-1]}),
    Case("token_with_extra_suffix", 401, server="token", body={"scene": "cornell-box"},
         headers={"Authorization": "Bearer " + TOKEN + "x"}),
    Case("token_without_scheme", 401, server="token", body={"scene": "cornell-box"},
         headers={"Authorization": TOKEN}),
    Case("token_as_basic_auth", 401, server="token", body={"scene": "cornell-box"},
         headers={"Authorization": "Basic " + TOKEN}),
    Case("token_empty_bearer", 401, server="token", body={"scene": "cornell-box"},
         headers={"Authorization": "Bearer "}),
    Case("token_missing_on_delete", 401, server="token", method="DELETE",
         path=f"/api/jobs/{UNKNOWN_ID}"),
    Case("token_wrong_on_delete", 401, server="token", method="DELETE",
         path=f"/api/jobs/{UNKNOWN_ID}", headers={"Authorization": "Bearer wrong"}),
    Case("token_missing_on_cancel", 401, server="token", path=f"/api/jobs/{UNKNOWN_ID}/cancel"),
]
