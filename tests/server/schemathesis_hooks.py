"""Schemathesis extension hooks for test_schemathesis.py (loaded through $SCHEMATHESIS_HOOKS): the
mesh media types of POST /api/assets are sent as raw bytes, as application/octet-stream is."""

from schemathesis.serializers import OctetStreamSerializer, register

register("model/obj", aliases=("model/gltf-binary",))(OctetStreamSerializer)
