"""Stress scenes: where methods fail (scenes/stress/, and tests/scenes/ball-at-partition.gltf)."""

import colorsys
import math

from .gltf import Gltf, gltf_text, png_rgba
from .vecmath import cross, dot, normalize, oriented_triangles, sub
from .cornell import CORNELL_LIGHT_INTENSITY, CORNELL_LIGHT_POSITION, cornell_geometry
from .fixtures import ball_node
from .solids import box_solid, camera_node, quat_look, solid_node, vec
from .rooms import (
    DOOR_HEIGHT, DOOR_WIDTH, DOOR_Z, ROOMS_CAMERA, ROOMS_CAMERA_TARGET, ROOMS_DEPTH, ROOMS_HEIGHT,
    ROOMS_LIGHT, ROOMS_LIGHT_INTENSITY, ROOMS_PARTITION, ROOMS_SHELL, ROOMS_WHITE, ROOMS_WIDTH, finish_scene,
    rooms_build,
)


# The leak scenes above are fair to a renderer: every wall is a closed solid reaching into its
# neighbours. Each scene below breaks one such convention the way exported models do (see
# docs/scenes.md, "Stress scenes: where methods fail"). Their scene extras say what a test may
# assume, so that tests do not repeat constants:
#   purpose             one sentence: what the scene is for
#   dark_min, dark_max  a closed world-space box the light cannot reach: every surface point in
#                       it, seen from inside the box, has radiance exactly 0 for a leak-free
#                       method and for the reference (a zero-thickness wall lying in the box's
#                       boundary is lit on its other side: photon tests need a margin there)
#   expected            method -> outcome, one of the tokens below
#   radius              the gather radius the scene is about (only where it is about one)
#   scale               every length is the unscaled layout's times this; intensities times its square
EXPECT_ZERO = "zero_in_dark"         # exactly 0 at every surface point in dark_min/max
EXPECT_LEAKS = "leaks"               # brighter than the reference on a wall's dark side (> 0 in dark_min/max)
EXPECT_LIT = "nonzero_in_room_b"     # real light reaches the camera's room (through a gap or holes)
EXPECT_MATCH = "matches_reference"   # within noise of the reference
EXPECT_FINITE = "finite"             # every pixel finite and non-negative; nothing more is claimed


def sealed_expectations():
    """A light in one room, the camera in a sealed other room, a radius wider than the wall."""
    return {"direct": EXPECT_ZERO, "reference": EXPECT_ZERO, "splat": EXPECT_LEAKS,
            "leakless": EXPECT_ZERO, "leakless-capped": EXPECT_ZERO}


def r6(x):
    """Rounded to the micrometre (no float noise like 0.8999999999999999 in the files), no -0.0."""
    return round(x, 6) + 0.0


def restyle(extras, purpose, **more):
    """A rooms_build extras dict for a stress scene: `purpose` first, no `description`."""
    out = {"purpose": purpose}
    out.update((k, v) for k, v in extras.items() if k != "description")
    out.update(more)
    return out


def room_b_not_dark(extras, room_a_lit=True):
    """rooms_build's dark_room_min/max renamed room_b_min/max, where light does reach room B
    (and lit_room_min/max room_a_min/max where the light leaves room A)."""
    def name(k):
        if k.startswith("dark_room"):
            return "room_b" + k[len("dark_room"):]
        if k.startswith("lit_room") and not room_a_lit:
            return "room_a" + k[len("lit_room"):]
        return k
    return {name(k): v for k, v in extras.items()}


def oriented_indices(positions, quad, toward):
    """The two triangles (flat index list) of `quad` (4 vertex indices in cyclic order), wound
    counter-clockwise seen from the side where the point `toward` lies."""
    a, b, c, d = quad
    n = cross(sub(positions[b], positions[a]), sub(positions[c], positions[a]))
    centre = tuple(sum(positions[i][k] for i in quad) / 4 for k in range(3))
    return [a, b, c, a, c, d] if dot(n, sub(toward, centre)) > 0 else [a, c, b, a, d, c]


# The zero-thickness layout of sealed-quads and the partition sweep: the two-rooms rooms (3 m ×
# 2.5 m × 3 m each, along x), but every wall, floor and ceiling a single quad with nothing
# behind it, the rooms' end walls at x = ±3 and the partition centred on x = 0.
QUADS_X1 = ROOMS_WIDTH
PARTITION_SWEEP_MM = (0, 1, 10, 50)
SEALED_QUADS_BIG = 1000.0  # sealed-quads-x1000: the same file at 1000 × (3 km rooms)


def sealed_quads(scale=1.0):
    """Both rooms as ONE indexed mesh of 11 quads over 12 shared vertices: the partition's
    edges are the floor's, ceiling's and side walls' edges, and nothing overlaps anywhere."""
    g = Gltf()
    white = g.material("white", ROOMS_WHITE)
    h, x1, z1 = ROOMS_HEIGHT, QUADS_X1, ROOMS_DEPTH / 2
    sc = lambda p: tuple(scale * c + 0.0 for c in p)
    positions = [sc((x, y, z)) for x in (-x1, 0.0, x1) for y in (0.0, h) for z in (-z1, z1)]
    v = lambda i, j, k: 4 * i + 2 * j + k  # x, y, z grid indices -> vertex
    room_a, room_b = sc((-x1 / 2, h / 2, 0.0)), sc((x1 / 2, h / 2, 0.0))
    quads = []
    for i, centre in ((0, room_a), (1, room_b)):  # room A spans x grid lines 0-1, room B 1-2
        quads += [([v(i, 0, 0), v(i + 1, 0, 0), v(i + 1, 0, 1), v(i, 0, 1)], centre),  # floor
                  ([v(i, 1, 0), v(i + 1, 1, 0), v(i + 1, 1, 1), v(i, 1, 1)], centre),  # ceiling
                  ([v(i, 0, 0), v(i + 1, 0, 0), v(i + 1, 1, 0), v(i, 1, 0)], centre),  # back wall
                  ([v(i, 0, 1), v(i + 1, 0, 1), v(i + 1, 1, 1), v(i, 1, 1)], centre)]  # front wall
    end = lambda i: [v(i, 0, 0), v(i, 1, 0), v(i, 1, 1), v(i, 0, 1)]
    # End walls, then the partition, which faces room B (the camera's): its normal points away
    # from the light, so a method that trusts the stored normal on a lit two-sided surface errs.
    quads += [(end(0), room_a), (end(2), room_b), (end(1), room_b)]
    indices = [i for q, toward in quads for i in oriented_indices(positions, q, toward)]
    mesh = g.mesh("sealed quads", positions, None, white, indices=indices)
    nodes = [g.add("nodes", {"name": "sealed quads", "mesh": mesh})]
    intensity = ROOMS_LIGHT_INTENSITY * scale ** 2
    nodes.append(g.light("room A light", {"name": "room A light", "type": "point", "color": [1.0, 1.0, 1.0],
                                          "intensity": intensity}, translation=list(sc(ROOMS_LIGHT))))
    nodes.append(camera_node(g, "room B camera", sc(ROOMS_CAMERA), sc(ROOMS_CAMERA_TARGET), znear=0.02 * scale))
    extras = {
        "purpose": "two rooms sealed only by shared edges and vertices of single quads in one indexed mesh "
                   "(zero-thickness walls, no NORMAL attribute): room B must stay exactly black",
        "units": "m",
        "scale": scale,
        "albedo": ROOMS_WHITE[0],
        "partition_x": 0.0,
        "partition_thickness": 0.0,
        "lit_room_min": vec(sc((-x1, 0.0, -z1))),
        "lit_room_max": vec(sc((0.0, h, z1))),
        "dark_min": vec(sc((0.0, 0.0, -z1))),
        "dark_max": vec(sc((x1, h, z1))),
        "light_intensity_w_per_sr": intensity,
        "expected": sealed_expectations(),
    }
    name = "sealed quads" if scale == 1.0 else "sealed quads x%g" % scale
    return finish_scene(g, name, nodes, extras)


def partition_sweep(mm):
    """The sealed-quads layout as separate unindexed meshes, one per wall, with a partition
    `mm` thick: a single quad at 0, else a closed thin box whose bottom, top and side faces are
    the strips of floor, ceiling and side walls between the rooms (sharing their edges)."""
    g, nodes, extras = partition_sweep_build(mm)
    nodes.append(camera_node(g, "room B camera", ROOMS_CAMERA, ROOMS_CAMERA_TARGET))
    return finish_scene(g, f"partition {mm} mm", nodes, extras)


def partition_sweep_build(mm):
    """partition_sweep's walls, partition and light, and its extras: (g, nodes, extras)."""
    g = Gltf()
    white = g.material("white", ROOMS_WHITE)
    h, x1, z1 = ROOMS_HEIGHT, QUADS_X1, ROOMS_DEPTH / 2
    thickness = mm / 1000
    t = thickness / 2
    nodes = []

    def quad(name, corners, toward):
        nodes.append(solid_node(g, name, oriented_triangles([corners], True, toward), white))

    for room, xa, xb, xe in (("A", -x1, -t + 0.0, -x1), ("B", t, x1, x1)):
        centre = ((xa + xb) / 2, h / 2, 0.0)
        quad(f"room {room} floor", [(xa, 0.0, -z1), (xb, 0.0, -z1), (xb, 0.0, z1), (xa, 0.0, z1)], centre)
        quad(f"room {room} ceiling", [(xa, h, -z1), (xb, h, -z1), (xb, h, z1), (xa, h, z1)], centre)
        quad(f"room {room} back wall", [(xa, 0.0, -z1), (xb, 0.0, -z1), (xb, h, -z1), (xa, h, -z1)], centre)
        quad(f"room {room} front wall", [(xa, 0.0, z1), (xb, 0.0, z1), (xb, h, z1), (xa, h, z1)], centre)
        quad(f"room {room} end wall", [(xe, 0.0, -z1), (xe, h, -z1), (xe, h, z1), (xe, 0.0, z1)], centre)
    if mm == 0:
        quad("partition", [(0.0, 0.0, -z1), (0.0, h, -z1), (0.0, h, z1), (0.0, 0.0, z1)], (1.0, h / 2, 0.0))
    else:
        nodes.append(solid_node(g, "partition", box_solid((-t, 0.0, -z1), (t, h, z1)), white))
    nodes.append(g.light("room A light", {"name": "room A light", "type": "point", "color": [1.0, 1.0, 1.0],
                                          "intensity": ROOMS_LIGHT_INTENSITY}, translation=list(ROOMS_LIGHT)))
    extras = {
        "purpose": f"partition thickness sweep ({mm} mm here): walls are quads or a thin box sharing edges with "
                   "the floor and ceiling; the same layout, light and camera at every thickness, so leaked "
                   "energy can be charted against thickness",
        "units": "m",
        "thickness": thickness,
        "partition_thickness": thickness,
        "sweep_mm": list(PARTITION_SWEEP_MM),
        "albedo": ROOMS_WHITE[0],
        "partition_x": 0.0,
        "partition_min": vec((-t, 0.0, -z1)),
        "partition_max": vec((t, h, z1)),
        "lit_room_min": vec((-x1, 0.0, -z1)),
        "lit_room_max": vec((-t, h, z1)),
        "dark_min": vec((t, 0.0, -z1)),
        "dark_max": vec((x1, h, z1)),
        "light_intensity_w_per_sr": ROOMS_LIGHT_INTENSITY,
        "expected": sealed_expectations(),
    }
    return g, nodes, extras


# ball-at-partition.gltf: partition-0mm.gltf with a smooth tessellated ball in the dark room, 2 cm
# from the partition, and the camera between them, looking along the partition at the ball's
# side that faces it. leakless lifts the visibility segments of a convex curved surface by κr²
# (gather.comp), here more than the gap: a lift not stopped at the partition starts segments in
# the lit room, and photons on the partition's lit face, within 10° of the ball's tangent planes,
# would count.
BALL_AT_PARTITION_RADIUS = 0.12
BALL_AT_PARTITION_GAP = 0.02
BALL_AT_PARTITION_CENTRE = (BALL_AT_PARTITION_GAP + BALL_AT_PARTITION_RADIUS, 0.6, 0.0)
BALL_AT_PARTITION_EYE = (0.03, 0.65, -0.9)


def ball_at_partition():
    g, nodes, extras = partition_sweep_build(0)
    r, c = BALL_AT_PARTITION_RADIUS, BALL_AT_PARTITION_CENTRE
    nodes.append(ball_node(g, c, r))
    nodes.append(camera_node(g, "room B camera", BALL_AT_PARTITION_EYE, c))
    extras["purpose"] = ("a smooth ball in the dark room 2 cm from a sealed 0 mm partition, seen from between "
                         "them: visibility segments lifted off a curved surface must not start in the lit room")
    extras.update({"ball_centre": vec(c), "ball_radius": r, "ball_gap": BALL_AT_PARTITION_GAP})
    return finish_scene(g, "ball at partition", nodes, extras)


# The door leaf of door-gap.gltf and door.gltf: a 4 cm box on room A's side of the doorway,
# 5 cm larger than the opening at both jambs and the head, its room-B face 5 mm inside the 2 cm
# partition. Closed, it fills the whole cross-section of the opening between x = -0.01 and
# -0.005 (doorway.gltf's opening runs from the floor slab, y = -0.05, up to 2 m), so together
# with the partition it seals room B by overlapping volumes, with no contact to rely on.
DOOR_LEAF_THICKNESS = 0.04
DOOR_LEAF_OVERLAP = 0.05   # past the opening at both jambs and at the head
DOOR_LEAF_INSET = 0.005    # its room-B face this far inside the partition
DOOR_LEAF_FOOT = -0.04     # door.gltf: its bottom, 4 cm down in the 10 cm floor slab
DOOR_GAP = 0.01            # door-gap.gltf: its bottom, 1 cm above the floor
DOOR_COLOR = (0.45, 0.3, 0.18)
DOOR_CLOSED_TIME = 2.0
DOOR_OPEN_DEGREES = -90.0  # about +Y through the hinge: the open leaf stands in room A


def door_hinge():
    """The hinge axis (vertical) passes through this point: the leaf's room-B face, at the jamb
    at z = DOOR_Z[0] minus the overlap."""
    return (r6(-ROOMS_PARTITION / 2 + DOOR_LEAF_INSET), 0.0, r6(DOOR_Z[0] - DOOR_LEAF_OVERLAP))


def door_leaf_local(bottom):
    """The leaf's box in the hinge frame (hinge at the origin; closed = no rotation)."""
    return ((-DOOR_LEAF_THICKNESS, bottom, 0.0),
            (0.0, r6(DOOR_HEIGHT + DOOR_LEAF_OVERLAP), r6(DOOR_WIDTH + 2 * DOOR_LEAF_OVERLAP)))


def door_leaf_world(bottom):
    lo, hi = door_leaf_local(bottom)
    hx, hy, hz = door_hinge()
    return (r6(hx + lo[0]), r6(hy + lo[1]), r6(hz + lo[2])), (r6(hx + hi[0]), r6(hy + hi[1]), r6(hz + hi[2]))


def door_gap():
    g, nodes, extras = rooms_build(door=True)
    wood = g.material("door", DOOR_COLOR)
    lo, hi = door_leaf_world(DOOR_GAP)
    nodes.insert(-2, solid_node(g, "door leaf", box_solid(lo, hi), wood))
    t = ROOMS_PARTITION / 2
    extras = restyle(
        extras, "a closed door whose leaf stops 1 cm above the floor: real light reaches room B through the "
                "gap (after a bounce: no straight line from the light passes through it into room B)",
        leaf_min=vec(lo), leaf_max=vec(hi),
        gap_height=DOOR_GAP,
        gap_min=vec((lo[0], 0.0, DOOR_Z[0])), gap_max=vec((t, DOOR_GAP, DOOR_Z[1])),
        # The light (1.8 m up) would have to dive below 1 cm within the leaf's 4 cm and rise
        # again: every straight segment from it into room B is blocked, so direct light there is
        # exactly 0, while the reference is not.
        direct_dark_min=extras["dark_room_min"], direct_dark_max=extras["dark_room_max"],
        expected={"direct": "zero_in_direct_dark", "reference": EXPECT_LIT, "splat": EXPECT_LEAKS,
                  "leakless": EXPECT_MATCH, "leakless-capped": EXPECT_LIT})
    return finish_scene(g, "door gap", nodes, room_b_not_dark(extras))


# light-near-wall: the two-rooms layout with a 5 cm partition and the light 1 cm from its
# room-A face: 40 % of the light's power lands within 5 cm of the hot spot (20 000 W/m² at
# its centre), right behind room B's side of the wall.
NEAR_WALL_PARTITION = 0.05
NEAR_WALL_GAP = 0.01
NEAR_WALL_LIGHT = (-(NEAR_WALL_PARTITION / 2 + NEAR_WALL_GAP), 1.25, 0.0)
NEAR_WALL_EYE_A = (-2.6, 1.6, 1.2)


def light_near_wall(camera_in_b):
    hot = (-NEAR_WALL_PARTITION / 2, NEAR_WALL_LIGHT[1], NEAR_WALL_LIGHT[2])
    if camera_in_b:
        eye, target, cam = ROOMS_CAMERA, (-hot[0], hot[1], hot[2]), "room B camera"
    else:
        eye, target, cam = NEAR_WALL_EYE_A, hot, "room A camera"
    g, nodes, extras = rooms_build(door=False, thickness=NEAR_WALL_PARTITION, light=NEAR_WALL_LIGHT,
                                   eye=eye, target=target, camera_name=cam)
    view = ("the camera in dark room B looks at the wall right behind the hot spot" if camera_in_b else
            "the camera in room A looks at the hot spot")
    extras = restyle(
        extras, f"a point light 1 cm from a 5 cm partition: extreme photon density at the hot spot; {view}",
        light_wall_distance=NEAR_WALL_GAP,
        hot_spot=vec(hot),
        hot_spot_irradiance_w_per_m2=ROOMS_LIGHT_INTENSITY / NEAR_WALL_GAP ** 2,
        dark_min=extras["dark_room_min"], dark_max=extras["dark_room_max"],
        expected=sealed_expectations())
    return finish_scene(g, "light near wall" + (" (dark side)" if camera_in_b else ""), nodes, extras)


# coplanar: an interior wall modelled as exported flats often are, a 10 cm box whose top face
# lies in the ceiling's underside, its bottom face in the floor's top and its ends in the side
# walls' inner faces (embed 0: it touches, nothing overlaps), and in room A a rug: a second
# floor quad, coplanar with the floor slab's top face, with another albedo (z-fighting).
COPLANAR_PARTITION = 0.1
COPLANAR_RUG = ((-1.8, -1.0), (-0.3, 0.8))   # (x0, z0), (x1, z1) at y = 0
COPLANAR_RUG_COLOR = (0.15, 0.3, 0.6)
COPLANAR_EYE_A = (-2.85, 1.5, 1.1)
COPLANAR_TARGET_A = (-0.05, 1.0, -0.2)


def coplanar(camera_in_b):
    t = COPLANAR_PARTITION / 2
    if camera_in_b:
        eye, target, cam = ROOMS_CAMERA, (t, 1.05, -0.2), "room B camera"
    else:
        eye, target, cam = COPLANAR_EYE_A, COPLANAR_TARGET_A, "room A camera"
    g, nodes, extras = rooms_build(door=False, thickness=COPLANAR_PARTITION, embed=0.0,
                                   eye=eye, target=target, camera_name=cam)
    blue = g.material("rug", COPLANAR_RUG_COLOR)
    (x0, z0), (x1, z1) = COPLANAR_RUG
    rug = oriented_triangles([[(x0, 0.0, z0), (x1, 0.0, z0), (x1, 0.0, z1), (x0, 0.0, z1)]], True, (x0, 1.0, z0))
    nodes.insert(-2, solid_node(g, "rug", rug, blue))
    view = ("the camera in dark room B sees the wall's junctions" if camera_in_b else
            "the camera in room A sees the rug and the wall's lit face")
    extras = restyle(
        extras, "coplanar faces: a wall box touching floor, ceiling and side walls only along shared planes "
                f"(T-junctions, no overlap), and a rug quad z-fighting with the floor; {view}",
        rug_min=vec((x0, 0.0, z0)), rug_max=vec((x1, 0.0, z1)),
        rug_albedo=list(COPLANAR_RUG_COLOR), floor_albedo=list(ROOMS_WHITE),
        dark_min=extras["dark_room_min"], dark_max=extras["dark_room_max"],
        expected=sealed_expectations())
    return finish_scene(g, "coplanar" + (" (dark side)" if camera_in_b else ""), nodes, extras)


# lattice: a window in the 2 cm partition filled by a screen, one quad in the partition's
# mid-plane textured with a lattice whose holes have alpha 0 (alphaMode MASK, cutoff 0.5).
# Texels are 2.5 cm; the screen reaches 2 texels (5 cm) into the partition around the window;
# inside the window, 7 bars of 2 texels (two along the window's edges) frame 6 × 6 holes of
# 8 × 8 texels (20 cm). The pattern's edges fall on texel boundaries, where bilinear filtering
# crosses alpha 0.5, so nearest and bilinear sampling cut the same holes (but for the corners).
LATTICE_TEXEL = 0.025
LATTICE_MARGIN = 2                       # texels hidden in the partition on every side
LATTICE_CELL, LATTICE_BAR, LATTICE_CELLS = 10, 2, 6
LATTICE_TEXELS = 2 * LATTICE_MARGIN + LATTICE_CELLS * LATTICE_CELL + LATTICE_BAR  # 66
LATTICE_WINDOW_BOTTOM = 0.45
LATTICE_COLOR = (0.6, 0.45, 0.3)
LATTICE_CAMERA_EYE = (2.2, 1.3, 1.3)
LATTICE_CAMERA_TARGET = (0.0, 0.95, -0.1)


def lattice_opaque(i):
    """Whether texel column (or row) i is bar (or margin) along that axis."""
    m = LATTICE_MARGIN
    return i < m or i >= LATTICE_TEXELS - m or (i - m) % LATTICE_CELL < LATTICE_BAR


def lattice():
    n, tx = LATTICE_TEXELS, LATTICE_TEXEL
    half = n * tx / 2                                   # the screen: z in ±half
    inner = (n - 2 * LATTICE_MARGIN) * tx               # the window: 1.55 m square
    y0 = LATTICE_WINDOW_BOTTOM
    window = (y0, r6(y0 + inner), r6(-inner / 2), r6(inner / 2))
    top = r6(window[1] + LATTICE_MARGIN * tx)           # the screen's top edge (texel row 0)
    g, nodes, extras = rooms_build(door=False, window=window, eye=LATTICE_CAMERA_EYE, target=LATTICE_CAMERA_TARGET)
    texels = [(255, 255, 255, 255 if lattice_opaque(i) or lattice_opaque(j) else 0)
              for j in range(n) for i in range(n)]
    img = g.add("images", {"name": "lattice", "mimeType": "image/png", "bufferView": g.view(png_rgba(n, n, texels))})
    tex = g.add("textures", {"source": img})
    mat = g.material("lattice", LATTICE_COLOR, pbr={"baseColorTexture": {"index": tex}},
                     alphaMode="MASK", alphaCutoff=0.5)
    bottom = r6(top - n * tx)
    quad = [(0.0, top, -r6(half)), (0.0, top, r6(half)), (0.0, bottom, r6(half)), (0.0, bottom, -r6(half))]
    uvs = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]       # u along +z, v down from the top
    indices = oriented_indices(quad, [0, 1, 2, 3], (1.0, 1.0, 0.0))  # faces room B
    mesh = g.mesh("lattice screen", quad, [(1.0, 0.0, 0.0)] * 4, mat, uvs=uvs, indices=indices)
    nodes.insert(-2, g.add("nodes", {"name": "lattice screen", "mesh": mesh}))

    # A hole's and a bar's centre on the screen, and where the line from the light through
    # them meets room B's floor: directly lit, and in the bar's shadow.
    def through(texel_col, texel_row):
        s = (0.0, top - texel_row * tx, -half + texel_col * tx)
        L = ROOMS_LIGHT
        u = L[1] / (L[1] - s[1])                     # light + u (s - light) is on the floor
        return vec(tuple(r6(L[k] + u * (s[k] - L[k])) for k in range(3)))

    m, c, b = LATTICE_MARGIN, LATTICE_CELL, LATTICE_BAR
    hole = lambda k: m + k * c + (b + c) / 2   # texel coordinate of the centre of hole k
    bar = lambda k: m + k * c + b / 2          # ... and of bar k (bar 0 runs along the window's edge)
    extras = restyle(
        extras, "an alpha-masked lattice (PNG alpha, MASK, cutoff 0.5) in a window between the lit room and "
                "the camera's room: light passes through the holes only",
        window_min=vec((-ROOMS_PARTITION / 2, window[0], window[2])),
        window_max=vec((ROOMS_PARTITION / 2, window[1], window[3])),
        screen_x=0.0,
        texel_size=tx,
        hole_size=(LATTICE_CELL - LATTICE_BAR) * tx,
        bar_width=LATTICE_BAR * tx,
        alpha_cutoff=0.5,
        open_fraction=(LATTICE_CELLS * (LATTICE_CELL - LATTICE_BAR) / (n - 2 * LATTICE_MARGIN)) ** 2,
        direct_lit_point=through(hole(3), hole(LATTICE_CELLS - 1)),
        direct_shadow_point=through(hole(3), bar(LATTICE_CELLS - 1)),
        expected={"direct": EXPECT_LIT, "reference": EXPECT_LIT, "splat": EXPECT_LEAKS,
                  "leakless": EXPECT_MATCH, "leakless-capped": EXPECT_LIT})
    return finish_scene(g, "lattice", nodes, room_b_not_dark(extras))


# room-1mm, room-10km, big-radius: two-rooms.gltf itself (thick overlapping walls, a 2 cm
# partition), scaled about the origin; the light intensity times scale², so every image is the
# same as two-rooms' (the default gather radius, 5 % of the scene's size, scales with it).
ROOM_1MM_SCALE = 0.001 / ROOMS_WIDTH       # each 3 m room 1 mm across
ROOM_10KM_SCALE = 10000.0 / ROOMS_WIDTH    # each room 10 km across
BIG_RADIUS_SCALE = 1.0 / 3.0               # 1 m rooms
BIG_RADIUS = 3.0                           # wider than the whole scene (its diagonal is 2.5 m)


def scaled_rooms(scale, name, purpose, **more):
    g, nodes, extras = rooms_build(door=False, scale=scale)
    extras = restyle(extras, purpose, scale=scale, dark_min=extras["dark_room_min"],
                     dark_max=extras["dark_room_max"], expected=sealed_expectations(), **more)
    return finish_scene(g, name, nodes, extras)


def room_1mm():
    return scaled_rooms(ROOM_1MM_SCALE, "two rooms 1 mm",
                        "two-rooms scaled so that each room is 1 mm across (the partition is 6.7 µm): "
                        "the same image as two-rooms; absolute epsilons fail here")


def room_10km():
    return scaled_rooms(ROOM_10KM_SCALE, "two rooms 10 km",
                        "two-rooms scaled so that each room is 10 km across (float32 spacing ~1 mm): "
                        "the same image as two-rooms; absolute epsilons fail here")


def big_radius():
    lo = (-(ROOMS_PARTITION / 2 + ROOMS_WIDTH + ROOMS_SHELL), -ROOMS_SHELL, -(ROOMS_DEPTH / 2 + ROOMS_SHELL))
    diagonal = 2 * math.sqrt(lo[0] ** 2 + ((ROOMS_HEIGHT + 2 * ROOMS_SHELL) / 2) ** 2 + lo[2] ** 2) * BIG_RADIUS_SCALE
    return scaled_rooms(BIG_RADIUS_SCALE, "big radius",
                        "two-rooms at 1/3 scale (1 m rooms) with a gather radius wider than the whole scene: "
                        "every photon is within the radius of every view sample",
                        radius=BIG_RADIUS, scene_diagonal=r6(diagonal))


# camera-in-wall: the two-rooms layout with a 20 cm partition (reaching 5 cm into the shell)
# and the camera's eye inside it, 7 cm from its room-A face and 13 cm from its room-B face,
# looking along it (-z, a little down). The raster G-buffer clips what is nearer than znear
# (20 cm), so the pixels far to the left see through the room-A face into the lit room (about
# 27 % of the image) and those far to the right through the room-B face into the dark room
# (8 %); the middle two thirds see the wall's inside faces, or the floor, ceiling and back
# wall faces that run through the wall's inside, where no light goes.
WALL_BOX_THICKNESS = 0.2
CAMERA_IN_WALL_EYE = (-0.03, 1.4, 1.2)
CAMERA_IN_WALL_TARGET = (-0.03, 1.2, -1.2)
CAMERA_IN_WALL_ZNEAR = 0.2


def camera_in_wall():
    t = WALL_BOX_THICKNESS / 2
    g, nodes, extras = rooms_build(door=False, thickness=WALL_BOX_THICKNESS, eye=CAMERA_IN_WALL_EYE,
                                   target=CAMERA_IN_WALL_TARGET, znear=CAMERA_IN_WALL_ZNEAR,
                                   camera_name="camera in the wall")
    z1 = ROOMS_DEPTH / 2
    extras = restyle(
        extras, "the camera's eye inside a 20 cm wall box, looking along it: some pixels see the wall's "
                "inside faces (unlit), others, past the near plane, the lit room beyond",
        eye=vec(CAMERA_IN_WALL_EYE), znear=CAMERA_IN_WALL_ZNEAR,
        wall_inside_min=vec((-t, 0.0, -z1)), wall_inside_max=vec((t, ROOMS_HEIGHT, z1)),
        # Room B and the wall's inside: one box, unlit seen from inside it.
        dark_min=vec((-t, 0.0, -z1)), dark_max=extras["dark_room_max"],
        expected=sealed_expectations())
    return finish_scene(g, "camera in wall", nodes, extras)


# far-degenerate: a closed 4 m × 2.5 m × 3 m room, one indexed mesh, under a node translated to
# (1e6, 0, 1e6) m, where float32 positions are 1/16 m apart. All its local coordinates are
# multiples of 1/16 m, so the world-space vertices are exact; the light and camera positions too.
# Four zero-area triangles are mixed in among the walls: a repeated vertex, a single point, three
# collinear vertices along the floor's edge and three collinear vertices in mid-air.
FAR_OFFSET = (1.0e6, 0.0, 1.0e6)
FAR_ROOM = ((-2.0, 0.0, -1.5), (2.0, 2.5, 1.5))
FAR_LIGHT = (0.5, 1.75, 0.25)
FAR_EYE = (1.75, 1.5, 1.25)
FAR_TARGET = (-1.0, 0.75, -0.75)
FAR_INTENSITY = 2.0


def far_degenerate():
    g = Gltf()
    white = g.material("white", ROOMS_WHITE)
    (x0, y0, z0), (x1, y1, z1) = FAR_ROOM
    centre = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
    faces = [
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],  # floor; its first edge is the back one
        [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)],  # ceiling
        [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)],  # back wall
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # front wall
        [(x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1)],  # left wall
        [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],  # right wall
    ]
    positions, normals, indices = [], [], []
    for f, corners in enumerate(faces):
        base = len(positions)
        positions += corners
        tris = oriented_indices(positions, [base, base + 1, base + 2, base + 3], centre)
        a, b, c = (positions[i] for i in tris[:3])
        normals += [normalize(cross(sub(b, a), sub(c, a)))] * 4
        indices += tris
        if f == 0:    # a repeated vertex, and one point three times
            indices += [base, base, base + 1, base + 2, base + 2, base + 2]
        elif f == 2:  # collinear, along the floor's back edge (shared by floor and back wall)
            positions.append(((x0 + x1) / 2, y0, z0))
            normals.append((0.0, 1.0, 0.0))
            indices += [0, len(positions) - 1, 1]
        elif f == 4:  # collinear, in mid-air across the room
            positions += [(-1.0, 1.25, 0.0), (0.0, 1.25, 0.0), (1.0, 1.25, 0.0)]
            normals += [(0.0, 1.0, 0.0)] * 3
            indices += [len(positions) - 3, len(positions) - 2, len(positions) - 1]
    mesh = g.mesh("far room", positions, normals, white, indices=indices)
    children = [g.add("nodes", {"name": "room", "mesh": mesh})]
    children.append(g.light("light", {"name": "light", "type": "point", "color": [1.0, 1.0, 1.0],
                                      "intensity": FAR_INTENSITY}, translation=list(FAR_LIGHT)))
    children.append(camera_node(g, "room camera", FAR_EYE, FAR_TARGET))
    root = g.add("nodes", {"name": "far away", "translation": list(FAR_OFFSET), "children": children})
    at = lambda p: vec(tuple(o + c for o, c in zip(FAR_OFFSET, p)))
    extras = {
        "purpose": "a lit closed room a million metres from the origin (float32 spacing 1/16 m), with "
                   "zero-area triangles mixed into its mesh",
        "units": "m",
        "offset": vec(FAR_OFFSET),
        "room_min": at(FAR_ROOM[0]),
        "room_max": at(FAR_ROOM[1]),
        "light_position": at(FAR_LIGHT),
        "light_intensity_w_per_sr": FAR_INTENSITY,
        "albedo": ROOMS_WHITE[0],
        "float32_spacing_at_offset": 0.0625,
        "degenerate_triangles": 4,
        "triangles": len(indices) // 3,
        "expected": {m: EXPECT_FINITE for m in ("direct", "reference", "splat", "leakless", "leakless-capped")},
    }
    return finish_scene(g, "far degenerate", [root], extras)


# hundred-lights: the Cornell box with its light replaced by 100 point lights of varied colour
# on a 10 × 10 grid 5 cm apart, at the original light's height. Each light's intensity times its
# colour's luminance is 1/100 of the Cornell light's 0.3 W/sr, so the luminance of the total
# power equals cornell-box.gltf's.
HUNDRED_SIDE = 10
HUNDRED_SPACING = 0.05


def hundred_lights():
    g = Gltf()
    nodes = cornell_geometry(g)
    n = HUNDRED_SIDE ** 2
    cx, y, cz = CORNELL_LIGHT_POSITION
    centre = (HUNDRED_SIDE - 1) / 2
    luminance_sum = 0.0
    for i in range(HUNDRED_SIDE):
        for k in range(HUNDRED_SIDE):
            index = i * HUNDRED_SIDE + k
            hue = (index * 0.6180339887498949) % 1.0  # golden-ratio steps: neighbours differ
            rgb = [round(c, 4) for c in colorsys.hsv_to_rgb(hue, 0.7, 1.0)]
            lum = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
            intensity = float("%.6g" % (CORNELL_LIGHT_INTENSITY / n / lum))
            luminance_sum += intensity * lum
            pos = (r6(cx + (i - centre) * HUNDRED_SPACING), y, r6(cz + (k - centre) * HUNDRED_SPACING))
            name = "light %02d" % index
            nodes.append(g.light(name, {"name": name, "type": "point", "color": rgb, "intensity": intensity},
                                 translation=list(pos)))
    half = centre * HUNDRED_SPACING
    extras = {
        "purpose": "the Cornell box lit by 100 coloured point lights on a grid, the luminance of their total "
                   "power equal to cornell-box.gltf's single light",
        "units": "m",
        "light_count": n,
        "light_grid_min": vec((r6(cx - half), y, r6(cz - half))),
        "light_grid_max": vec((r6(cx + half), y, r6(cz + half))),
        "per_light_intensity_times_luminance_w_per_sr": CORNELL_LIGHT_INTENSITY / n,
        "sum_intensity_times_luminance_w_per_sr": r6(luminance_sum),
        "cornell_light_intensity_w_per_sr": CORNELL_LIGHT_INTENSITY,
        "expected": {m: EXPECT_FINITE for m in ("direct", "reference", "splat", "leakless", "leakless-capped")},
    }
    g.doc["scene"] = g.add("scenes", {"name": "hundred lights", "nodes": nodes, "extras": extras})
    return gltf_text(g)


# grazing-spot: a closed 4 m × 2.5 m × 3 m room; a spot 2 cm in front of the back wall (z = -1.5)
# near its left end, its axis along +x turned 1.5° towards the wall (cones 0.05 / 0.1 rad). The
# axis meets the wall 0.76 m on; the rest of the cone lights a long streak of that wall at
# incidence angles of 1.5° to 7° from grazing, and the far end wall.
GRAZE_ROOM = ((-2.0, 0.0, -1.5), (2.0, 2.5, 1.5))
GRAZE_WALL_DISTANCE = 0.02
GRAZE_DEGREES = 1.5
GRAZE_POSITION = (-1.9, 1.25, -1.5 + GRAZE_WALL_DISTANCE)
GRAZE_CONES = (0.05, 0.1)
GRAZE_INTENSITY = 20.0
GRAZE_EYE = (0.0, 1.4, 1.3)
GRAZE_TARGET = (0.0, 1.2, -1.5)


def grazing_spot():
    g = Gltf()
    white = g.material("white", ROOMS_WHITE)
    (x0, y0, z0), (x1, y1, z1) = GRAZE_ROOM
    centre = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
    nodes = []
    for name, quad in (("floor", [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)]),
                       ("ceiling", [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)]),
                       ("back wall", [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)]),
                       ("front wall", [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]),
                       ("left wall", [(x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1)]),
                       ("right wall", [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)])):
        nodes.append(solid_node(g, name, oriented_triangles([quad], True, centre), white))
    a = math.radians(GRAZE_DEGREES)
    d = (math.cos(a), 0.0, -math.sin(a))
    inner, outer = GRAZE_CONES
    nodes.append(g.light("grazing spot", {"name": "grazing spot", "type": "spot", "color": [1.0, 1.0, 1.0],
                                          "intensity": GRAZE_INTENSITY,
                                          "spot": {"innerConeAngle": inner, "outerConeAngle": outer}},
                         translation=list(GRAZE_POSITION), rotation=quat_look(d)))
    nodes.append(camera_node(g, "room camera", GRAZE_EYE, GRAZE_TARGET))
    reach = GRAZE_WALL_DISTANCE / math.sin(a)          # along the axis to the wall
    irradiance = GRAZE_INTENSITY * math.sin(a) / reach ** 2
    extras = {
        "purpose": "a spot whose axis runs 1.5° off parallel to a wall, 2 cm from it: a long streak of light "
                   "at grazing incidence",
        "units": "m",
        "albedo": ROOMS_WHITE[0],
        "spot_position": vec(GRAZE_POSITION),
        "spot_direction": vec(d),
        "spot_intensity_w_per_sr": GRAZE_INTENSITY,
        "inner_cone": inner,
        "outer_cone": outer,
        "wall_z": z0,
        "wall_distance": GRAZE_WALL_DISTANCE,
        "axis_degrees_from_wall": GRAZE_DEGREES,
        "axis_wall_point": vec(tuple(r6(p + reach * c) for p, c in zip(GRAZE_POSITION, d))),
        "axis_wall_irradiance_w_per_m2": r6(irradiance),
        "axis_wall_direct_radiance": r6(ROOMS_WHITE[0] * irradiance / math.pi),
        "expected": {"direct": "matches_extras", "reference": "matches_extras", "splat": EXPECT_FINITE,
                     "leakless": EXPECT_FINITE, "leakless-capped": EXPECT_FINITE},
    }
    g.doc["scene"] = g.add("scenes", {"name": "grazing spot", "nodes": nodes, "extras": extras})
    return gltf_text(g)
