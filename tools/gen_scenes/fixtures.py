"""The scene crate's test fixtures (tests/scenes/)."""

import math

from .gltf import GENERATOR, Gltf, glb_bytes, gltf_text, png_rgba
from .vecmath import quat_axis_angle
from .cornell import cornell_geometry, cornell_light
from .sphere import icosphere


FLOOR_HALF_SIZE = 10.0
FLOOR_ALBEDO = 0.8
FLOOR_INTENSITY = 2.0
FLOOR_LIGHT_HEIGHT = 1.0


def floor_node(g, material):
    """The fixtures' floor: a square 2·FLOOR_HALF_SIZE wide at y = 0, facing up."""
    h = FLOOR_HALF_SIZE
    pos = [(-h, 0, h), (h, 0, h), (h, 0, -h), (-h, 0, h), (h, 0, -h), (-h, 0, -h)]
    return g.add("nodes", {"name": "floor", "mesh": g.mesh("floor", pos, [(0, 1, 0)] * 6, material)})


def light_and_camera(g, camera_height):
    """The point light FLOOR_LIGHT_HEIGHT above the floor's centre, and a camera
    `camera_height` above it looking straight down."""
    light = g.light("light", {"name": "light", "type": "point", "intensity": FLOOR_INTENSITY},
                    translation=[0.0, FLOOR_LIGHT_HEIGHT, 0.0])
    cam = g.add("cameras", {"name": "down", "type": "perspective", "perspective": {"yfov": math.radians(60), "znear": 0.01}})
    c = g.add("nodes", {"name": "camera", "camera": cam, "translation": [0.0, camera_height, 0.0],
                        "rotation": quat_axis_angle((1, 0, 0), -90)})
    return light, c


def floor_light():
    g = Gltf()
    floor = floor_node(g, g.material("floor", (FLOOR_ALBEDO,) * 3))
    light, c = light_and_camera(g, 2.0)
    g.doc["scene"] = g.add("scenes", {"name": "floor light", "nodes": [floor, light, c], "extras": {
        "albedo": FLOOR_ALBEDO, "intensity": FLOOR_INTENSITY, "light_height": FLOOR_LIGHT_HEIGHT,
        "expected_radiance_below_light": FLOOR_ALBEDO * FLOOR_INTENSITY / (math.pi * FLOOR_LIGHT_HEIGHT ** 2)}})
    return gltf_text(g)


# 2×2 RGBA texels, top row first: red, green / blue, white at half alpha.
TEXTURED_TEXELS = [(255, 0, 0, 255), (0, 255, 0, 255), (0, 0, 255, 255), (255, 255, 255, 128)]


def textured():
    """Exercises what the loader must get right: hierarchy transforms (T·R·S with
    non-uniform scale, a mirrored child), an embedded PNG, a spot and a directional
    light, and two ignored features (an animation and a normal texture)."""
    g = Gltf()
    img = g.add("images", {"name": "checker", "mimeType": "image/png",
                           "bufferView": g.view(png_rgba(2, 2, TEXTURED_TEXELS))})
    tex = g.add("textures", {"source": img})
    mat = g.material("checker", (1.0, 0.5, 0.25), pbr={"baseColorTexture": {"index": tex}},
                     normalTexture={"index": tex}, alphaMode="MASK", alphaCutoff=0.25)
    quad = [(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)]
    mesh = g.mesh("quad", quad, [(0, 0, 1)] * 4, mat, uvs=[(0, 1), (1, 1), (1, 0), (0, 0)],
                  indices=[0, 1, 2, 0, 2, 3])
    child = g.add("nodes", {"name": "child", "mesh": mesh, "translation": [0.0, 0.0, 1.0]})
    mirrored = g.add("nodes", {"name": "mirrored child", "mesh": mesh, "translation": [0.0, 0.0, -1.0],
                               "scale": [-1.0, 1.0, 1.0]})
    spot = g.light("spot", {"name": "spot", "type": "spot", "intensity": 5.0, "color": [1.0, 0.9, 0.8],
                            "range": 20.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
                   translation=[0.0, 1.0, 0.0])
    parent = g.add("nodes", {"name": "parent", "children": [child, mirrored, spot],
                             "translation": [1.0, 2.0, 3.0], "rotation": quat_axis_angle((0, 1, 0), 90),
                             "scale": [2.0, 3.0, 1.0]})
    sun = g.light("sun", {"name": "sun", "type": "directional", "intensity": 3.0},
                  rotation=quat_axis_angle((1, 0, 0), -45))
    times = g.accessor([0.0, 1.0], "SCALAR", target=None, minmax=True)
    moves = g.accessor([(0.0, 0.0, 1.0), (0.0, 0.0, 2.0)], "VEC3", target=None)
    g.add("animations", {"name": "slide", "samplers": [{"input": times, "output": moves}],
                         "channels": [{"sampler": 0, "target": {"node": child, "path": "translation"}}]})
    g.doc["scene"] = g.add("scenes", {"name": "textured", "nodes": [parent, sun]})
    return glb_bytes(g)


def occluder():
    """The floor-light floor and light, plus a small square occluder at half height off the
    light's axis: its shadow on the floor is centred at (1, 0, 0), 0.4 wide, and a camera
    high above sees that shadow past the occluder."""
    g = Gltf()
    white = g.material("floor", (FLOOR_ALBEDO,) * 3)
    grey = g.material("occluder", (0.5, 0.5, 0.5))
    floor = floor_node(g, white)
    a, b, y = 0.4, 0.6, 0.5
    quad = [(a, y, -0.1), (b, y, -0.1), (b, y, 0.1), (a, y, -0.1), (b, y, 0.1), (a, y, 0.1)]
    blocker = g.add("nodes", {"name": "occluder", "mesh": g.mesh("occluder", quad, [(0, 1, 0)] * 6, grey)})
    light, c = light_and_camera(g, 3.0)
    g.doc["scene"] = g.add("scenes", {"name": "occluder", "nodes": [floor, blocker, light, c]})
    return gltf_text(g)


CONVEX_BALL_CENTRE = (0.37, 0.12, 0.25)
CONVEX_BALL_RADIUS = 0.12
CONVEX_BALL_SUBDIVISIONS = 3  # 20 · 4^3 = 1280 facets, each about 1.3 cm across


def ball_node(g, centre, radius):
    """A grey smooth-shaded ball of CONVEX_BALL_SUBDIVISIONS (its normals are the unit sphere's)."""
    grey = g.material("ball", (0.7, 0.7, 0.7))
    unit, faces = icosphere(CONVEX_BALL_SUBDIVISIONS)
    positions = [tuple(c + radius * x for c, x in zip(centre, v)) for v in unit]
    indices = [i for f in faces for i in f]  # counter-clockwise seen from outside
    return g.add("nodes", {"name": "ball", "mesh": g.mesh("ball", positions, unit, grey, indices=indices)})


def convex_ball():
    """The Cornell box with a tessellated ball on its floor, beside the short block: a convex
    curved surface whose facets are smaller than the gather disk (tests/suite/corner_bias.rs)."""
    g = Gltf()
    nodes = cornell_geometry(g)
    nodes.append(ball_node(g, CONVEX_BALL_CENTRE, CONVEX_BALL_RADIUS))
    nodes.append(cornell_light(g))
    g.doc["scene"] = g.add("scenes", {"name": "convex ball", "nodes": nodes, "extras": {
        "ball_centre": list(CONVEX_BALL_CENTRE), "ball_radius": CONVEX_BALL_RADIUS}})
    return gltf_text(g)


SPOT_SUN_HALF_SIZE = 1.0
SPOT_SUN_HEIGHT = 1.0
SPOT_SUN_SPOT = {"intensity": 20.0, "color": [1.0, 0.8, 0.6], "inner": 0.2, "outer": 0.6}
SPOT_SUN_SUN = {"intensity": 2.0, "color": [0.6, 0.8, 1.0], "elevation_degrees": 45.0}


def spot_sun():
    """A 2 m × 2 m floor, a spot 1 m above its centre pointing straight down (outer cone
    0.6 rad: its footprint, radius tan 0.6 ≈ 0.68 m, lies on the floor, so all its light is
    caught) and a sun 45° high: the emitted flux of both kinds of light can be measured on
    the floor (the sun's as E·A·sin(elevation) over the floor's area A)."""
    g = Gltf()
    white = g.material("floor", (FLOOR_ALBEDO,) * 3)
    h = SPOT_SUN_HALF_SIZE
    pos = [(-h, 0, h), (h, 0, h), (h, 0, -h), (-h, 0, h), (h, 0, -h), (-h, 0, -h)]
    floor = g.add("nodes", {"name": "floor", "mesh": g.mesh("floor", pos, [(0, 1, 0)] * 6, white)})
    s = SPOT_SUN_SPOT
    spot = g.light("spot", {"name": "spot", "type": "spot", "intensity": s["intensity"], "color": s["color"],
                            "spot": {"innerConeAngle": s["inner"], "outerConeAngle": s["outer"]}},
                   translation=[0.0, SPOT_SUN_HEIGHT, 0.0], rotation=quat_axis_angle((1, 0, 0), -90))
    u = SPOT_SUN_SUN
    sun = g.light("sun", {"name": "sun", "type": "directional", "intensity": u["intensity"], "color": u["color"]},
                  rotation=quat_axis_angle((1, 0, 0), -u["elevation_degrees"]))
    g.doc["scene"] = g.add("scenes", {"name": "spot sun", "nodes": [floor, spot, sun], "extras": {
        "floor_half_size": h, "spot_height": SPOT_SUN_HEIGHT, "sun_elevation_degrees": u["elevation_degrees"]}})
    return gltf_text(g)


# 2×2 texels for the G-buffer texture test: red, green / blue, and a transparent white that
# alphaMode MASK must cut away.
QUAD_TEXELS = [(255, 0, 0, 255), (0, 255, 0, 255), (0, 0, 255, 255), (255, 255, 255, 0)]


def textured_quad():
    """A 2×2 quad facing a camera that it exactly fills (yfov = 2·atan(1/2) at distance 2),
    lit head-on by a directional light of irradiance π: radiance = albedo, texel by texel."""
    g = Gltf()
    img = g.add("images", {"name": "quadrants", "mimeType": "image/png",
                           "bufferView": g.view(png_rgba(2, 2, QUAD_TEXELS))})
    tex = g.add("textures", {"source": img})
    mat = g.material("quadrants", (1.0, 1.0, 1.0), pbr={"baseColorTexture": {"index": tex}},
                     alphaMode="MASK", alphaCutoff=0.5)
    quad = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    mesh = g.mesh("quad", quad, [(0, 0, 1)] * 4, mat, uvs=[(0, 1), (1, 1), (1, 0), (0, 0)],
                  indices=[0, 1, 2, 0, 2, 3])
    node = g.add("nodes", {"name": "quad", "mesh": mesh})
    sun = g.light("sun", {"name": "sun", "type": "directional", "intensity": math.pi})
    cam = g.add("cameras", {"name": "front", "type": "perspective",
                            "perspective": {"yfov": 2 * math.atan(0.5), "znear": 0.01}})
    c = g.add("nodes", {"name": "camera", "camera": cam, "translation": [0.0, 0.0, 2.0]})
    g.doc["scene"] = g.add("scenes", {"name": "textured quad", "nodes": [node, sun, c]})
    return gltf_text(g)


def no_light():
    g = Gltf()
    m = g.material("white", (0.8, 0.8, 0.8))
    mesh = g.mesh("triangle", [(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 0, 1)] * 3, m)
    g.doc["scene"] = g.add("scenes", {"nodes": [g.add("nodes", {"mesh": mesh})]})
    return gltf_text(g)


MALFORMED = b'{"asset": {"version": "2.0", "generator": "' + GENERATOR.encode() + \
    b'"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0,\n'
