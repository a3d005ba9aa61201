#!/usr/bin/env python3
"""Writes assets/analytic/torus.obj: a torus about +y with texture coordinates, normals and faces wound
counter-clockwise seen from outside. u goes once around the ring (the direction of increasing u, the
tangent MikkTSpace gives each vertex, is the ring's: normalize(-z, 0, x)), v once around the tube, so that
(u, v, normal) is right-handed. The seam's vertices are doubled, as every texture's seam is.

Usage: scripts/make-torus-obj.py [OUT]   (default assets/analytic/torus.obj)
"""
import math
import sys

RING_RADIUS, TUBE_RADIUS = 1.0, 0.4
RING_STEPS, TUBE_STEPS = 96, 24


def main(out):
    lines = [
        "# A torus about +y with texture coordinates: u around the ring, v around the tube.",
        "# Made by scripts/make-torus-obj.py; the tangent from u follows the ring.",
    ]
    for i in range(RING_STEPS + 1):
        phi = 2 * math.pi * i / RING_STEPS
        for j in range(TUBE_STEPS + 1):
            # theta turns so that d/du x d/dv is the outward normal.
            theta = -2 * math.pi * j / TUBE_STEPS
            n = (math.cos(theta) * math.cos(phi), math.sin(theta), math.cos(theta) * math.sin(phi))
            ring = RING_RADIUS + TUBE_RADIUS * math.cos(theta)
            p = (ring * math.cos(phi), TUBE_RADIUS * math.sin(theta), ring * math.sin(phi))
            lines.append("v %.5f %.5f %.5f" % p)
            lines.append("vt %.5f %.5f" % (i / RING_STEPS, j / TUBE_STEPS))
            lines.append("vn %.5f %.5f %.5f" % n)
    index = lambda i, j: i * (TUBE_STEPS + 1) + j + 1
    for i in range(RING_STEPS):
        for j in range(TUBE_STEPS):
            a, b, c, d = index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)
            for tri in ((a, b, c), (a, c, d)):
                lines.append("f " + " ".join("%d/%d/%d" % (k, k, k) for k in tri))
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "assets/analytic/torus.obj")
