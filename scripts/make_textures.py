#!/usr/bin/env python3
"""Writes the example scenes' textures as binary PPM (P6) files; scripts/make_textures.sh turns them
into PNG through oiiotool. All procedural, so that the repository holds their source:

  tiles.ppm         base colour (sRGB): 8 x 8 glazed tiles, each a slightly different green-grey,
                    in light grout
  tiles-mr.ppm      glTF metallic-roughness (linear): roughness 0.2 on a tile, 0.85 in the grout
                    (G), metallic 0 (B)
  tiles-normal.ppm  tangent-space normal map (linear, +y up the image): grout grooves with bevels
  spot-pattern.ppm  base colour in Spot's texture layout: cream with red polka dots and a band

Usage: scripts/make_textures.py OUT_DIR
"""
import math
import os
import random
import sys

SIZE = 512
TILES = 8
GROUT = 0.06  # of a tile's width
BEVEL = 0.05


def write_ppm(path, size, pixel):
    rows = bytearray()
    for y in range(size):
        for x in range(size):
            rows += bytes(max(0, min(255, round(255 * c))) for c in pixel(x, y))
    with open(path, "wb") as f:
        f.write(b"P6 %d %d 255\n" % (size, size))
        f.write(rows)


def tile_coords(x, y):
    """The tile a texel is in and its position within it, in [0, 1)."""
    u, v = (x + 0.5) / SIZE * TILES, (y + 0.5) / SIZE * TILES
    return int(u), int(v), u - int(u), v - int(v)


def grout_distance(fu, fv):
    """Distance from a tile's edge, in tile widths (0 at the edge)."""
    return min(fu, 1 - fu, fv, 1 - fv)


random.seed(38)
TINT = [[(0.33 + random.uniform(-0.04, 0.04), 0.42 + random.uniform(-0.05, 0.05),
          0.38 + random.uniform(-0.04, 0.04)) for _ in range(TILES)] for _ in range(TILES)]


def tiles(x, y):
    i, j, fu, fv = tile_coords(x, y)
    if grout_distance(fu, fv) < GROUT / 2:
        return (0.82, 0.8, 0.76)
    return TINT[j][i]


def tiles_mr(x, y):
    _, _, fu, fv = tile_coords(x, y)
    return (0.0, 0.85 if grout_distance(fu, fv) < GROUT / 2 else 0.2, 0.0)


def tiles_normal(x, y):
    _, _, fu, fv = tile_coords(x, y)
    d = grout_distance(fu, fv) - GROUT / 2
    nx = ny = 0.0
    if 0 <= d < BEVEL:
        # The bevel slopes down towards the nearest edge: the normal leans away from the tile.
        slope = 0.8 * (1 - d / BEVEL)
        edges = {fu: (-1, 0), 1 - fu: (1, 0), fv: (0, 1), 1 - fv: (0, -1)}  # +y is up the image
        ex, ey = edges[min(edges)]
        nx, ny = ex * slope, ey * slope
    length = math.sqrt(nx * nx + ny * ny + 1)
    return (0.5 + 0.5 * nx / length, 0.5 + 0.5 * ny / length, 0.5 + 0.5 / length)


def spot_pattern(x, y):
    u, v = (x + 0.5) / SIZE, (y + 0.5) / SIZE
    if abs(v - 0.62) < 0.03:
        return (0.1, 0.25, 0.6)
    cu, cv = (u * 12) % 1 - 0.5, (v * 12) % 1 - 0.5
    if cu * cu + cv * cv < 0.09:
        return (0.75, 0.08, 0.06)
    return (0.93, 0.86, 0.72)


def main():
    out = sys.argv[1]
    for name, pixel in [("tiles", tiles), ("tiles-mr", tiles_mr), ("tiles-normal", tiles_normal),
                        ("spot-pattern", spot_pattern)]:
        write_ppm(os.path.join(out, name + ".ppm"), SIZE, pixel)


if __name__ == "__main__":
    main()
