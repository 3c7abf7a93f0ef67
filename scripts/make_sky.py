#!/usr/bin/env python3
"""Writes the example scenes' sky: an equirectangular radiance map (Mitsuba 3's envmap layout, as
docs/scene-format.md "Environment" describes) of a clear afternoon sky with a small sun, as a
Radiance .hdr; scripts/make_sky.sh turns it into assets/meshes/sky.exr. An analytic sketch, not a
physical sky model: a blue zenith fading to a pale horizon, a glow around the sun, a grey-brown
ground, and a sun disk 0.6 degrees in radius whose irradiance is about ten times the sky's.

Usage: scripts/make_sky.py OUT.hdr [WIDTH]
"""
import math
import struct
import sys

SUN_ELEVATION = math.radians(28.0)
SUN_AZIMUTH = math.radians(-40.0)  # phi of the map: u = phi / 2 pi
SUN_RADIUS = math.radians(0.6)
SUN_RADIANCE = (52000.0, 47000.0, 40000.0)
GROUND = (0.30, 0.27, 0.24)


def direction(u, v):
    """The map's direction at (u, v): u = atan2(x, -z) / 2 pi, v = theta / pi from +y."""
    phi, theta = 2.0 * math.pi * u, math.pi * v
    return (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))


SUN = direction(SUN_AZIMUTH / (2 * math.pi) % 1.0, 0.5 - SUN_ELEVATION / math.pi)


def radiance(d):
    cos_sun = sum(a * b for a, b in zip(d, SUN))
    gamma = math.acos(max(-1.0, min(1.0, cos_sun)))
    if gamma < SUN_RADIUS:
        return SUN_RADIANCE
    y = d[1]
    if y < 0.0:
        return GROUND
    t = y ** 0.5
    horizon, zenith = (1.05, 1.0, 0.95), (0.22, 0.42, 0.95)
    glow = 1.6 * math.exp(-gamma / 0.12) + 0.25 * math.exp(-gamma / 0.6)
    return tuple(h * (1 - t) + z * t + glow * g for h, z, g in zip(horizon, zenith, (1.0, 0.85, 0.65)))


def rgbe(c):
    m = max(c)
    if m < 1e-32:
        return b"\0\0\0\0"
    mantissa, exponent = math.frexp(m)
    scale = mantissa * 256.0 / m
    return bytes([int(c[0] * scale), int(c[1] * scale), int(c[2] * scale), exponent + 128])


def main():
    out = sys.argv[1]
    width = int(sys.argv[2]) if len(sys.argv) > 2 else 1024
    height = width // 2
    with open(out, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {height} +X {width}\n".encode())
        for j in range(height):
            row = bytearray()
            for i in range(width):
                # Supersampled 3 x 3, so the sun's disk covers its texels by area.
                acc = [0.0, 0.0, 0.0]
                for sj in range(3):
                    for si in range(3):
                        c = radiance(direction((i + (si + 0.5) / 3) / width, (j + (sj + 0.5) / 3) / height))
                        acc = [a + b / 9.0 for a, b in zip(acc, c)]
                row += rgbe(acc)
            f.write(row)


if __name__ == "__main__":
    main()
