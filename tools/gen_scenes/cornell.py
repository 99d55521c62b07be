"""The Cornell box (scenes/cornell-box.gltf)."""

import math

from .gltf import Gltf, gltf_text
from .vecmath import oriented_triangles


# The Cornell Box measured data (Cornell University Program of Computer Graphics,
# "Cornell Box Data", graphics.cornell.edu/online/box/data.html), in millimetres.
# Their frame is right-handed with +Y up; the camera sits at z = -800 looking down +Z,
# so the red wall (x ≈ 556) is on the left and the green wall (x = 0) on the right.
CORNELL_MM = {
    "floor": [(552.8, 0, 0), (0, 0, 0), (0, 0, 559.2), (549.6, 0, 559.2)],
    "ceiling": [(556, 548.8, 0), (556, 548.8, 559.2), (0, 548.8, 559.2), (0, 548.8, 0)],
    "back wall": [(549.6, 0, 559.2), (0, 0, 559.2), (0, 548.8, 559.2), (556, 548.8, 559.2)],
    "right wall": [(0, 0, 559.2), (0, 0, 0), (0, 548.8, 0), (0, 548.8, 559.2)],
    "left wall": [(552.8, 0, 0), (549.6, 0, 559.2), (556, 548.8, 559.2), (556, 548.8, 0)],
}
CORNELL_SHORT_BLOCK_MM = [
    [(130, 165, 65), (82, 165, 225), (240, 165, 272), (290, 165, 114)],
    [(290, 0, 114), (290, 165, 114), (240, 165, 272), (240, 0, 272)],
    [(130, 0, 65), (130, 165, 65), (290, 165, 114), (290, 0, 114)],
    [(82, 0, 225), (82, 165, 225), (130, 165, 65), (130, 0, 65)],
    [(240, 0, 272), (240, 165, 272), (82, 165, 225), (82, 0, 225)],
]
CORNELL_TALL_BLOCK_MM = [
    [(423, 330, 247), (265, 330, 296), (314, 330, 456), (472, 330, 406)],
    [(423, 0, 247), (423, 330, 247), (472, 330, 406), (472, 0, 406)],
    [(472, 0, 406), (472, 330, 406), (314, 330, 456), (314, 0, 456)],
    [(314, 0, 456), (314, 330, 456), (265, 330, 296), (265, 0, 296)],
    [(265, 0, 296), (265, 330, 296), (423, 330, 247), (423, 0, 247)],
]
CORNELL_WHITE = (0.725, 0.71, 0.68)
CORNELL_RED = (0.63, 0.065, 0.05)
CORNELL_GREEN = (0.14, 0.45, 0.091)
# The point light replaces the measured 130 × 105 mm ceiling lamp: below the lamp's centre
# (x 278, z 279.5 mm), 10 cm below the ceiling (548.8 mm). Closer, the ceiling right above
# it becomes a tiny hot spot (irradiance ∝ 1/d²) that lights the room indirectly but that
# cosine-sampled paths rarely find: at 2 cm the reference path tracer still had 20 % RMS
# noise in the indirect layer after 1024 samples per pixel.
CORNELL_LIGHT_POSITION = (0.278, 0.4488, 0.2795)
# Radiant intensity, W/sr (flux 4πI ≈ 3.8 W), chosen for exposure 1 with a plain clamp:
# the floor under the light gets I/d² ≈ 1.07 W/m² direct (radiance ρE/π ≈ 0.25), and a
# small CPU path tracer of this file (32×32 px, 64 paths/px, same light transport as
# the renderer's reference) measured pixel luminance (direct + indirect) of
# 0.11 / 0.28 / 0.55 / 1.04 at the 25th / 50th / 75th / 90th percentiles, mean
# radiance direct ≈ 0.30 and indirect ≈ 0.23: about 10 % of the image clips, the
# ceiling and the tops of the walls around the light, as around the real lamp.
# (1 W/sr, the usual guess, would clip about half of the image.)
CORNELL_LIGHT_INTENSITY = 0.3
CORNELL_CAMERA_POSITION = (0.278, 0.273, -0.800)
# 35 mm focal length on a 25 mm film: yfov = 2 atan(12.5 / 35) ≈ 39.3°.
CORNELL_YFOV = 2 * math.atan(12.5 / 35)


def cornell_light(g):
    return g.light("ceiling light", {"name": "ceiling light", "type": "point", "color": [1.0, 1.0, 1.0],
                                     "intensity": CORNELL_LIGHT_INTENSITY},
                   translation=list(CORNELL_LIGHT_POSITION))


def cornell_box():
    g = Gltf()
    nodes = cornell_geometry(g)
    nodes.append(cornell_light(g))
    g.doc["scene"] = g.add("scenes", {"name": "cornell box", "nodes": nodes, "extras": {
        "source": "Cornell Box Data, graphics.cornell.edu/online/box/data.html (mm -> m)",
        "light_intensity_w_per_sr": CORNELL_LIGHT_INTENSITY}})
    return gltf_text(g)


def cornell_geometry(g):
    """The box's materials, walls, blocks and camera; returns their nodes."""
    white = g.material("white", CORNELL_WHITE)
    red = g.material("red", CORNELL_RED)
    green = g.material("green", CORNELL_GREEN)
    mm = lambda quads: [[tuple(c / 1000 for c in p) for p in q] for q in quads]
    room_centre = (0.278, 0.274, 0.280)
    nodes = []
    for name, material in (("floor", white), ("ceiling", white), ("back wall", white),
                           ("left wall", red), ("right wall", green)):
        pos, nrm = oriented_triangles(mm([CORNELL_MM[name]]), True, room_centre)
        nodes.append(g.add("nodes", {"name": name, "mesh": g.mesh(name, pos, nrm, material)}))
    for name, quads in (("short block", CORNELL_SHORT_BLOCK_MM), ("tall block", CORNELL_TALL_BLOCK_MM)):
        quads = mm(quads)
        centre = tuple(sum(c) / (4 * len(quads)) for c in zip(*[p for q in quads for p in q]))
        centre = (centre[0], 0.0, centre[2])  # below the top face, inside the block
        pos, nrm = oriented_triangles(quads, False, centre)
        nodes.append(g.add("nodes", {"name": name, "mesh": g.mesh(name, pos, nrm, white)}))
    cam = g.add("cameras", {"name": "cornell camera", "type": "perspective", "perspective": {
        "yfov": CORNELL_YFOV, "znear": 0.05, "aspectRatio": 1.0}})
    # glTF cameras look down their -Z: turn 180° about +Y to look down world +Z.
    nodes.append(g.add("nodes", {"name": "camera", "camera": cam,
                                 "translation": list(CORNELL_CAMERA_POSITION),
                                 "rotation": [0.0, 1.0, 0.0, 0.0]}))
    return nodes
