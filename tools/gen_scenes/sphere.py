"""The closed sphere with a point light at its centre (scenes/sphere.gltf)."""

import math

from .gltf import Gltf, gltf_text
from .vecmath import normalize


SPHERE_RADIUS = 1.0
SPHERE_ALBEDO = 0.5
SPHERE_INTENSITY = 1.0
SPHERE_SUBDIVISIONS = 4  # 20 · 4^4 = 5120 triangles


def icosphere(subdivisions):
    t = (1 + math.sqrt(5)) / 2
    verts = [normalize(v) for v in [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                                    (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
             (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        midpoint = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                verts.append(normalize(tuple((x + y) / 2 for x, y in zip(verts[a], verts[b]))))
                midpoint[key] = len(verts) - 1
            return midpoint[key]

        faces = [f for a, b, c in faces for f in
                 ((a, mid(a, b), mid(c, a)), (b, mid(b, c), mid(a, b)), (c, mid(c, a), mid(b, c)),
                  (mid(a, b), mid(b, c), mid(c, a)))]
    return verts, faces


def sphere():
    g = Gltf()
    grey = g.material("grey", (SPHERE_ALBEDO,) * 3)
    unit, faces = icosphere(SPHERE_SUBDIVISIONS)
    positions = [tuple(SPHERE_RADIUS * x for x in v) for v in unit]
    # Normals point inward (towards the light and the camera, the side that is seen);
    # the icosphere's faces are counter-clockwise seen from outside, so reverse them.
    normals = [tuple(-x for x in v) for v in unit]
    indices = [i for a, b, c in faces for i in (a, c, b)]
    mesh = g.mesh("sphere", positions, normals, grey, indices=indices)
    s = g.add("nodes", {"name": "sphere", "mesh": mesh})
    light = g.light("centre light", {"name": "centre light", "type": "point", "intensity": SPHERE_INTENSITY})
    cam = g.add("cameras", {"name": "inside", "type": "perspective", "perspective": {"yfov": math.radians(60), "znear": 0.01}})
    # Slightly off centre (so the camera is not inside the light), looking down -Z at the wall.
    c = g.add("nodes", {"name": "camera", "camera": cam, "translation": [0.0, 0.0, 0.25]})
    # In a closed sphere every point sees every other with the same form factor, so the
    # radiance is uniform: direct ρI/(πR²), and all bounces sum to a geometric series.
    direct = SPHERE_ALBEDO * SPHERE_INTENSITY / (math.pi * SPHERE_RADIUS ** 2)
    total = direct / (1 - SPHERE_ALBEDO)
    g.doc["scene"] = g.add("scenes", {"name": "sphere", "nodes": [s, light, c], "extras": {
        "radius": SPHERE_RADIUS, "albedo": SPHERE_ALBEDO, "intensity": SPHERE_INTENSITY,
        "normals": "inward",
        "expected_direct_radiance": direct,
        "expected_indirect_radiance": total - direct,
        "expected_total_radiance": total}})
    return gltf_text(g)
