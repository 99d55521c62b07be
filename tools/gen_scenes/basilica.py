"""The game-scale basilica (scenes/basilica.glb, scenes/basilica-sealed.glb; denser variants on
request): smooth columns, balusters and pew slats narrower than the gather radius, sunlit
12 cm galleries over shaded aisles, an alpha-masked lattice, a textured floor, a sun, four
lanterns and a spot, and a walk down the nave.

Repeated parts (columns, balusters, pews) are one mesh each, placed by many nodes, as game
levels place them: the file stays small while the loader flattens every placement into
world-space triangles. `detail` scales the facet counts of the curved meshes, and so the
triangle count about in proportion (1: about 210k triangles)."""

import math

from .animated import camera_path
from .gltf import Gltf, glb_bytes, png_rgba
from .solids import box_solid, camera_node, grid_solid, quat_look, vec
from .sponza import sun_direction

# The building, metres: the nave between two arcades (x = ±6), an aisle under a gallery on
# each side out to the outer walls (x = ±12), 40 m long (z 0..40), 14 m to the roof.
HALF_WIDTH = 12.0
NAVE_HALF = 6.0
LENGTH = 40.0
HEIGHT = 14.0
WALL = 0.3
GALLERY = (6.0, 6.12)            # the galleries' 12 cm floors over the aisles (bottom, top)
WINDOW_Y = (8.0, 11.0)           # window band in the outer walls, above the galleries
WINDOW_WIDTH = 2.0
WINDOW_PITCH = 5.0
COLUMN_RADIUS = 0.35
COLUMN_ZS = [2.5 + 5.0 * i for i in range(8)]  # under the gallery edges, both sides
BALUSTER_PITCH = 0.25
BALUSTER_HEIGHT = 0.85
RAIL = 0.1                       # the balustrade rail's width and height
PEW_ROWS = [8.0 + 1.0 * i for i in range(20)]
SCREEN_Z = 34.0                  # the lattice (chancel) screen across the nave
SCREEN_HEIGHT = 4.5
STONE = (0.72, 0.69, 0.62)
WOOD = (0.42, 0.26, 0.14)
GALLERY_FLOOR = (0.74, 0.36, 0.2)
SUN_ELEVATION = 38.0
SUN_AZIMUTH = 70.0               # from +z towards +x: the sun stands beyond the +x wall
SUN_INTENSITY = 3.0
LANTERN_INTENSITY = 2.0          # W/sr
LANTERNS = [(-9.0, 4.0, 8.0), (-9.0, 4.0, 30.0), (9.0, 4.0, 8.0), (9.0, 4.0, 30.0)]
SPOT = ((0.0, 11.0, 37.0), 30.0)  # over the altar, pointing down; W/sr
CAMERA = ((3.0, 1.7, 3.0), (-8.0, 5.5, 16.0))
WALK = ((0.0, 2.0, 4.0), ((0.5, 1.7, 2.0), (-1.0, 1.7, 14.0), (1.5, 1.7, 26.0)),
        ((-6.0, 4.0, 14.0), (4.0, 5.0, 26.0), (-2.0, 2.0, 40.0)))
SEALED_CAMERA = ((9.0, 1.6, 3.0), (7.0, 2.5, 20.0))


def lathe(profile, around):
    """A smooth surface of revolution about +y: `profile` is [(y, r), ...] bottom to top;
    `around` facets. Vertex normals from the profile's slope, so the shading is smooth.
    Returns (positions, normals, indices)."""
    positions, normals, indices = [], [], []
    for j, (y, r) in enumerate(profile):
        y0, r0 = profile[max(j - 1, 0)]
        y1, r1 = profile[min(j + 1, len(profile) - 1)]
        slope = (r1 - r0) / (y1 - y0)  # dr/dy
        for i in range(around + 1):    # a seam column duplicated, as a UV seam would be
            a = 2.0 * math.pi * (i % around) / around
            c, s = math.cos(a), math.sin(a)
            positions.append((r * c, y, r * s))
            k = 1.0 / math.sqrt(1.0 + slope * slope)
            normals.append((c * k, -slope * k, s * k))
    ring = around + 1
    for j in range(len(profile) - 1):
        for i in range(around):
            a, b = j * ring + i, j * ring + i + 1
            c, d = a + ring, b + ring
            indices += [a, c, b, b, c, d]  # outward-facing
    return positions, normals, indices


def column_profile(rings):
    """A column from just under the floor to just inside the gallery floor, with entasis."""
    y0, y1 = -0.05, GALLERY[0] + 0.05
    out = []
    for j in range(rings + 1):
        t = j / rings
        out.append((y0 + (y1 - y0) * t, COLUMN_RADIUS * (1.0 + 0.06 * math.sin(math.pi * t) - 0.05 * t)))
    return out


def baluster_profile(rings):
    """A turned baluster 4–7 cm in radius, standing on the gallery floor up into the rail."""
    y0, y1 = -0.02, BALUSTER_HEIGHT + 0.02
    out = []
    for j in range(rings + 1):
        t = j / rings
        r = 0.04 + 0.03 * math.sin(math.pi * min(1.0, 1.4 * t)) ** 2
        out.append((y0 + (y1 - y0) * t, r))
    return out


def with_uvs(solid, scale=1.0):
    """A solid's triangles with texture coordinates from world position (the two axes across
    each face), `scale` repeats per metre."""
    pos, nrm = solid
    uvs = []
    for p, n in zip(pos, nrm):
        axis = max(range(3), key=lambda a: abs(n[a]))
        u, v = [p[a] for a in range(3) if a != axis]
        uvs.append((u * scale, v * scale))
    return pos, nrm, uvs


def pew_boxes():
    """One pew, 4.2 m long along x from 0, seat slats and back slats 2–3 cm thick with gaps."""
    boxes = []
    length = 4.2
    for k in range(3):  # seat slats
        z = 0.05 + 0.12 * k
        boxes.append(((0.05, 0.42, z), (length - 0.05, 0.45, z + 0.10)))
    for k in range(4):  # back slats
        y = 0.55 + 0.12 * k
        boxes.append(((0.05, y, 0.36), (length - 0.05, y + 0.08, 0.38)))
    for x in (0.0, length - 0.05):  # end boards, reaching into the floor
        boxes.append(((x, -0.02, 0.0), (x + 0.05, 1.0, 0.42)))
    return boxes


def checker_png():
    """Floor tiles: 8×8 texels, two marbles."""
    light, dark = (214, 204, 186, 255), (120, 104, 92, 255)
    return png_rgba(8, 8, [light if (x // 4 + y // 4) % 2 == 0 else dark for y in range(8) for x in range(8)])


def lattice_png():
    """A lattice: a 2-texel opaque frame around transparent 6×6 holes (alpha-masked)."""
    bar, hole = (60, 40, 24, 255), (0, 0, 0, 0)
    return png_rgba(8, 8, [bar if x < 2 or y < 2 else hole for y in range(8) for x in range(8)])


def texture(g, name, png):
    img = g.add("images", {"name": name, "mimeType": "image/png", "bufferView": g.view(png)})
    return g.add("textures", {"source": img})


def outer_wall(x0, x1):
    """An outer wall from x0 to x1 with the window band cut out of it, closed box cells."""
    zs = [-WALL]
    for k in range(int(LENGTH / WINDOW_PITCH)):
        mid = WINDOW_PITCH * (k + 0.5)
        zs += [mid - WINDOW_WIDTH / 2, mid + WINDOW_WIDTH / 2]
    zs.append(LENGTH + WALL)
    ys = [-0.1, WINDOW_Y[0], WINDOW_Y[1], HEIGHT]
    return grid_solid((x0, x1), ys, zs, lambda i, j, k: not (j == 1 and k % 2 == 1))


def basilica(detail=1.0, sealed=False):
    g = Gltf()
    stone = g.material("stone", STONE)
    wood = g.material("wood", WOOD)
    gallery_floor = g.material("gallery floor", GALLERY_FLOOR)
    floor = g.material("floor tiles", (1.0, 1.0, 1.0),
                       pbr={"baseColorTexture": {"index": texture(g, "tiles", checker_png())}})
    lattice = g.material("lattice", (1.0, 1.0, 1.0), alphaMode="MASK", alphaCutoff=0.5,
                         pbr={"baseColorTexture": {"index": texture(g, "lattice", lattice_png())}})
    f = math.sqrt(detail)
    W, N, L, H, T = HALF_WIDTH, NAVE_HALF, LENGTH, HEIGHT, WALL
    nodes = []

    def solid(name, s, material):
        pos, nrm = s
        return g.add("nodes", {"name": name, "mesh": g.mesh(name, pos, nrm, material)})

    fp, fn, fu = with_uvs(box_solid((-W - T, -0.3, -T), (W + T, 0.0, L + T)), 0.5)
    nodes.append(g.add("nodes", {"name": "floor", "mesh": g.mesh("floor", fp, fn, floor, uvs=fu)}))
    nodes.append(solid("east outer wall", outer_wall(W, W + T), stone))
    nodes.append(solid("west outer wall", outer_wall(-W - T, -W), stone))
    nodes.append(solid("entrance wall", box_solid((-W - T, -0.1, -T), (W + T, H, 0.0)), stone))
    nodes.append(solid("apse wall", box_solid((-W - T, -0.1, L), (W + T, H, L + T)), stone))
    nodes.append(solid("roof", box_solid((-W - T, H, -T), (W + T, H + 0.3, L + T)), stone))
    for side in (-1, 1):
        # From over the columns' tops (which end inside it) into the outer wall.
        inner, outer = side * (N - 1.3 * COLUMN_RADIUS), side * (W + T / 2)
        lo, hi = (min(inner, outer), GALLERY[0], -T / 2), (max(inner, outer), GALLERY[1], L + T / 2)
        pos, nrm = box_solid(lo, hi)
        for name, top, mat in (("gallery soffit", False, stone), ("gallery floor", True, gallery_floor)):
            idx = [i for i in range(len(pos)) if (nrm[i][1] > 0.5) == top]
            nodes.append(solid(f"{name} {side:+d}", ([pos[i] for i in idx], [nrm[i] for i in idx]), mat))
        # The balustrade's rail; the balusters stand under it.
        rail_x = side * (N + 0.05)
        nodes.append(solid(f"rail {side:+d}", box_solid((rail_x - RAIL / 2, GALLERY[1] + BALUSTER_HEIGHT, -T / 2),
                                                        (rail_x + RAIL / 2, GALLERY[1] + BALUSTER_HEIGHT + RAIL,
                                                         L + T / 2)), stone))
    if sealed:
        # The east aisle, under the sunlit gallery, closed off along its arcade: a wall through
        # the column line, from under the floor into the gallery floor and the end walls.
        nodes.append(solid("arcade wall", box_solid((N - 0.15, -0.1, -T / 2), (N + 0.2, GALLERY[0] + 0.06, L + T / 2)),
                           stone))

    around, rings = max(6, round(64 * f)), max(3, round(40 * f))
    cp, cn, ci = lathe(column_profile(rings), around)
    column = g.mesh("column", cp, cn, stone, indices=ci)
    b_around, b_rings = max(4, round(16 * f)), max(2, round(12 * f))
    bp, bn, bi = lathe(baluster_profile(b_rings), b_around)
    baluster = g.mesh("baluster", bp, bn, stone, indices=bi)
    pew_solid = ([], [])
    for lo, hi in pew_boxes():
        p, n = box_solid(lo, hi)
        pew_solid[0].extend(p)
        pew_solid[1].extend(n)
    pew = g.mesh("pew", pew_solid[0], pew_solid[1], wood)
    for side in (-1, 1):
        for z in COLUMN_ZS:
            nodes.append(g.add("nodes", {"name": "column", "mesh": column, "translation": vec((side * N, 0.0, z))}))
        for k in range(int(L / BALUSTER_PITCH)):
            at = (side * (N + 0.05), GALLERY[1], BALUSTER_PITCH * (k + 0.5))
            nodes.append(g.add("nodes", {"name": "baluster", "mesh": baluster, "translation": vec(at)}))
    for z in PEW_ROWS:
        for x in (-5.0, 0.8):
            nodes.append(g.add("nodes", {"name": "pew", "mesh": pew, "translation": vec((x, 0.0, z))}))
    # The chancel screen: one alpha-masked quad across the nave, 8 lattice cells a metre.
    x0, x1, y1 = -N + COLUMN_RADIUS, N - COLUMN_RADIUS, SCREEN_HEIGHT
    quad = [(x0, 0.0, SCREEN_Z), (x1, 0.0, SCREEN_Z), (x1, y1, SCREEN_Z), (x0, y1, SCREEN_Z)]
    uv = [(p[0] * 4.0, p[1] * 4.0) for p in quad]
    nodes.append(g.add("nodes", {"name": "screen", "mesh": g.mesh(
        "screen", [quad[i] for i in (0, 1, 2, 0, 2, 3)], [(0.0, 0.0, 1.0)] * 6, lattice,
        uvs=[uv[i] for i in (0, 1, 2, 0, 2, 3)])}))

    d = sun_direction(SUN_ELEVATION, SUN_AZIMUTH)
    nodes.append(g.light("sun", {"name": "sun", "type": "directional", "color": [1.0, 0.93, 0.8],
                                 "intensity": SUN_INTENSITY}, rotation=quat_look(d)))
    for i, at in enumerate(LANTERNS):
        if sealed and at[0] > 0:
            continue  # the sealed aisle gets no light of its own
        nodes.append(g.light(f"lantern {i + 1}", {"name": f"lantern {i + 1}", "type": "point",
                                                  "color": [1.0, 0.75, 0.45], "intensity": LANTERN_INTENSITY},
                             translation=vec(at)))
    spot_at, spot_w = SPOT
    nodes.append(g.light("altar spot", {"name": "altar spot", "type": "spot", "color": [1.0, 0.95, 0.9],
                                        "intensity": spot_w, "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.45}},
                         translation=vec(spot_at), rotation=quat_look((0.0, -1.0, 0.0))))
    eye, target = SEALED_CAMERA if sealed else CAMERA
    nodes.append(camera_node(g, "camera", eye, target))
    description = ("a basilica 24 m × 40 m: smooth columns, balusters and pew slats narrower than the gather "
                   "radius; 12 cm galleries over the aisles, sunlit through the outer walls' windows; an "
                   "alpha-masked chancel screen, a tiled floor, four lanterns in the aisles and a spot on the altar")
    if sealed:
        description += ("; the east aisle, under the sunlit gallery, is walled off along its arcade and has no "
                        "light: the camera stands in it, and everything it sees must be exactly black")
    else:
        times, eyes, targets = WALK
        camera_path(g, nodes[-1], "walk down the nave", times, eyes, targets)
        description += "; the camera walks down the nave over 4 s"
    g.doc["scene"] = g.add("scenes", {"name": "basilica", "nodes": nodes, "extras": {
        "description": description,
        "units": "m",
        "detail": detail,
        "sealed_aisle_min": vec((N + 0.2, 0.0, 0.0)),
        "sealed_aisle_max": vec((W, GALLERY[0], L)),
        "gallery_floor_bottom_y": GALLERY[0],
        "gallery_floor_top_y": GALLERY[1],
        "column_radius": COLUMN_RADIUS,
        "sun_direction": vec(d)}})
    return glb_bytes(g)
