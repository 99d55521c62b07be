"""Two rooms, one thin wall (scenes/two-rooms.gltf, scenes/doorway.gltf)."""

from .gltf import Gltf, gltf_text
from .solids import box_solid, camera_node, grid_solid, solid_node, vec


# Two 3 m × 2.5 m × 3 m rooms side by side along x, inside one closed shell of 10 cm slabs,
# separated by a 2 cm partition at x = 0. Room A (x < 0) holds the light; room B (x > 0), where
# the camera is, receives no light at all: any light a renderer shows there crossed the wall.
ROOMS_WIDTH = 3.0        # along x, each room
ROOMS_HEIGHT = 2.5
ROOMS_DEPTH = 3.0        # along z
ROOMS_PARTITION = 0.02   # partition thickness
ROOMS_SHELL = 0.1        # shell slab thickness
ROOMS_EMBED = 0.05       # how far the partition reaches into the shell slabs
ROOMS_WHITE = (0.7, 0.7, 0.7)
ROOMS_RED = (0.63, 0.065, 0.05)
# 2 W/sr: the floor below the light gets I/h² ≈ 0.62 W/m² direct (radiance ρE/π ≈ 0.14).
ROOMS_LIGHT_INTENSITY = 2.0
ROOMS_LIGHT = (-1.2, 1.8, 0.3)
ROOMS_CAMERA = (2.85, 1.5, 1.1)
ROOMS_CAMERA_TARGET = (0.0, 1.05, -0.2)
DOOR_WIDTH, DOOR_HEIGHT = 0.8, 2.0
DOOR_Z = (0.35, 0.35 + DOOR_WIDTH)
DOOR_CAMERA = (2.85, 1.5, -1.2)
DOOR_CAMERA_TARGET = (0.0, 0.9, 0.45)


def rooms(door):
    """The shell, the partition (with a doorway when `door`), the light, the camera."""
    g, nodes, extras = rooms_build(door)
    return finish_scene(g, "doorway" if door else "two rooms", nodes, extras)


def rooms_build(door, thickness=ROOMS_PARTITION, embed=ROOMS_EMBED, scale=1.0, window=None,
                light=ROOMS_LIGHT, eye=None, target=None, znear=0.02, camera_name="room B camera"):
    """The two-rooms builder, returning (g, nodes, extras) so that variants can add to it.

    thickness: the partition's; embed: how far it reaches into the shell (0: its faces lie in
    the planes of the floor, ceiling and side walls); scale: every length (and znear) times
    `scale`, the light intensity times scale² so the image stays the same; window:
    (y0, y1, z0, z1) of an opening in the partition that does not reach the floor (door
    takes precedence); eye and target: the camera (default: the two-rooms or doorway view);
    light None: no point light (the caller adds its own)."""
    g = Gltf()
    white = g.material("white", ROOMS_WHITE)
    red = g.material("red", ROOMS_RED)
    h, t, s, e = ROOMS_HEIGHT, thickness / 2, ROOMS_SHELL, embed
    x1 = t + ROOMS_WIDTH                  # inner face of room B's end wall (room A: -x1)
    z1 = ROOMS_DEPTH / 2                  # inner faces of the side walls at ±z1
    sc = lambda p: tuple(scale * c for c in p)
    node = lambda name, solid, mat: solid_node(g, name, ([sc(p) for p in solid[0]], solid[1]), mat)
    nodes = []
    # Shell: floor and ceiling slabs under/over everything, end walls and side walls reaching
    # into them, so every inner corner is closed by overlapping solids, not by shared edges.
    nodes.append(node("floor", box_solid((-x1 - s, -s, -z1 - s), (x1 + s, 0.0, z1 + s)), white))
    nodes.append(node("ceiling", box_solid((-x1 - s, h, -z1 - s), (x1 + s, h + s, z1 + s)), white))
    nodes.append(node("room A end wall", box_solid((-x1 - s, -s, -z1 - s), (-x1, h + s, z1 + s)), white))
    nodes.append(node("room B end wall", box_solid((x1, -s, -z1 - s), (x1 + s, h + s, z1 + s)), white))
    nodes.append(node("back wall", box_solid((-x1 - s, -s, -z1 - s), (x1 + s, h + s, -z1)), white))
    nodes.append(node("front wall", box_solid((-x1 - s, -s, z1), (x1 + s, h + s, z1 + s)), white))
    # The partition reaches `embed` (ROOMS_EMBED) into the floor, ceiling and side walls: nothing
    # can pass around its edges. Its room-A face is red, so light that leaks is visibly red.
    if door:
        ys = (0.0 - e, DOOR_HEIGHT, h + e)
        zs = (-z1 - e, DOOR_Z[0], DOOR_Z[1], z1 + e)
        is_hole = lambda i, j, k: j == 0 and k == 1
    elif window:
        ys = (0.0 - e, window[0], window[1], h + e)
        zs = (-z1 - e, window[2], window[3], z1 + e)
        is_hole = lambda i, j, k: j == 1 and k == 1
    else:
        ys, zs = (0.0 - e, h + e), (-z1 - e, z1 + e)
        is_hole = lambda i, j, k: False
    pos, nrm = grid_solid((-t, t), ys, zs, lambda i, j, k: not is_hole(i, j, k))
    a_side = [n[0] < -0.5 for n in nrm]
    for name, keep, mat in (("partition", lambda a: not a, white), ("partition room A face", lambda a: a, red)):
        idx = [i for i in range(len(pos)) if keep(a_side[i])]
        nodes.append(node(name, ([pos[i] for i in idx], [nrm[i] for i in idx]), mat))
    intensity = ROOMS_LIGHT_INTENSITY * scale ** 2
    if light is not None:
        nodes.append(g.light("room A light", {"name": "room A light", "type": "point", "color": [1.0, 1.0, 1.0],
                                              "intensity": intensity},
                             translation=list(sc(light))))
    if eye is None:
        eye, target = (DOOR_CAMERA, DOOR_CAMERA_TARGET) if door else (ROOMS_CAMERA, ROOMS_CAMERA_TARGET)
    nodes.append(camera_node(g, camera_name, sc(eye), sc(target), znear=znear * scale))
    extras = {
        "description": ("two rooms in one closed shell, a doorway in the 2 cm partition" if door else
                        "two rooms in one closed shell, sealed by a 2 cm partition: room B gets no light"),
        "units": "m",
        "albedo": ROOMS_WHITE[0],
        "partition_x": 0.0,
        "partition_thickness": thickness * scale,
        "partition_min": vec(sc((-t, 0.0, -z1))),
        "partition_max": vec(sc((t, h, z1))),
        "lit_room_min": vec(sc((-x1, 0.0, -z1))),
        "lit_room_max": vec(sc((-t, h, z1))),
        "dark_room_min": vec(sc((t, 0.0, -z1))),
        "dark_room_max": vec(sc((x1, h, z1))),
        "light_intensity_w_per_sr": intensity,
    }
    if door:
        extras["door_min"] = vec(sc((-t, 0.0, DOOR_Z[0])))
        extras["door_max"] = vec(sc((t, DOOR_HEIGHT, DOOR_Z[1])))
    elif not window:
        extras["expected_dark_room_radiance"] = 0.0
    return g, nodes, extras


def finish_scene(g, name, nodes, extras):
    g.doc["scene"] = g.add("scenes", {"name": name, "nodes": nodes, "extras": extras})
    return gltf_text(g)


def two_rooms():
    return rooms(door=False)


def doorway():
    return rooms(door=True)
