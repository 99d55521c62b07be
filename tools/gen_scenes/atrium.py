"""The sunlit atrium (scenes/atrium.gltf)."""

from .gltf import Gltf, gltf_text
from .solids import box_solid, camera_node, quat_look, solid_node, vec
from .sponza import sun_direction


# A courtyard open to the sky, 12 m (x) × 8 m (z), walled on four sides 7 m high. Along the
# back wall (z = -3) runs a 3 m deep two-storey gallery: a ground-floor gallery under a thin
# (15 cm) upper slab carried by six piers and a beam, and on the slab an open terrace. The back
# wall is one slab over both storeys. The sun, 55° high, comes over the front wall and strikes
# the terrace and the upper back wall; the back wall below the slab is in its shadow, and the
# camera stands in the ground-floor gallery looking along it at the wall just under the slab.
ATRIUM_HALF_WIDTH = 6.0      # courtyard inner faces at x = ±6
ATRIUM_BACK_Z = -3.0         # back wall inner face
ATRIUM_FRONT_Z = 8.0         # front wall inner face
ATRIUM_WALL_HEIGHT = 7.0
ATRIUM_WALL = 0.3            # wall thickness
ATRIUM_SLAB = (3.35, 3.5)    # upper slab bottom and top
ATRIUM_SLAB_FRONT_Z = 0.0
ATRIUM_PIER = 0.4            # square piers, set ATRIUM_PIER_SETBACK behind the slab's front edge
ATRIUM_PIER_SETBACK = 0.05
ATRIUM_BEAM_RECESS = 0.03    # the beam's faces this far inside the piers' (no coplanar visible faces)
ATRIUM_PIER_XS = (-5.0, -3.0, -1.0, 1.0, 3.0, 5.0)
ATRIUM_BEAM_BOTTOM = 2.95
ATRIUM_STONE = (0.7, 0.66, 0.58)
ATRIUM_GROUND = (0.6, 0.6, 0.6)
ATRIUM_TERRACOTTA = (0.72, 0.32, 0.16)
ATRIUM_SUN_ELEVATION = 55.0  # degrees above the horizon
ATRIUM_SUN_AZIMUTH = 25.0    # degrees from +z towards +x (where the sun stands)
ATRIUM_SUN_INTENSITY = 3.0   # W/m², normal irradiance
ATRIUM_SUN_COLOR = [1.0, 0.93, 0.8]
ATRIUM_CAMERA = (5.4, 1.5, -1.7)
ATRIUM_CAMERA_TARGET = (-2.0, 2.9, -2.9)
# atrium-pan (the motion benchmark's): from the atrium's view, along the gallery under the slab
# (between the back wall and the piers), turning out towards the courtyard.
ATRIUM_PAN_TIMES = (0.0, 2.0, 4.0)
ATRIUM_PAN_EYES = (ATRIUM_CAMERA, (1.5, 1.5, -1.7), (-2.5, 1.5, -1.7))
ATRIUM_PAN_TARGETS = (ATRIUM_CAMERA_TARGET, (-3.0, 2.2, -0.8), (-6.0, 1.6, 2.5))

# atrium-orbit (the motion benchmark's fast camera): from the courtyard, the camera swings on
# an arc of radius 5.5 m about a point under the slab's front edge, from 80° west to 80° east
# of the courtyard's axis in 2 s and back in 2 s (80°/s), looking at that point all along.
ATRIUM_ORBIT_PIVOT = (0.0, 2.5, 0.0)
ATRIUM_ORBIT_RADIUS = 5.5
ATRIUM_ORBIT_HEIGHT = 1.8
ATRIUM_ORBIT_DEGREES = tuple(range(-80, 81, 20)) + tuple(range(60, -81, -20))


def atrium_orbit_path():
    """(times, eyes, targets) of the orbit: a keyframe every 20° (0.25 s)."""
    import math
    px, _, pz = ATRIUM_ORBIT_PIVOT
    eyes = [(round(px + ATRIUM_ORBIT_RADIUS * math.sin(math.radians(a)), 6), ATRIUM_ORBIT_HEIGHT,
             round(pz + ATRIUM_ORBIT_RADIUS * math.cos(math.radians(a)), 6)) for a in ATRIUM_ORBIT_DEGREES]
    times = [0.25 * k for k in range(len(eyes))]
    return times, eyes, [ATRIUM_ORBIT_PIVOT] * len(eyes)


def atrium_sun_direction():
    """Direction the sunlight travels (unit, downward)."""
    return sun_direction(ATRIUM_SUN_ELEVATION, ATRIUM_SUN_AZIMUTH)


def atrium(pan=False, orbit=False):
    g = Gltf()
    stone = g.material("stone", ATRIUM_STONE)
    ground = g.material("ground", ATRIUM_GROUND)
    terracotta = g.material("terracotta", ATRIUM_TERRACOTTA)
    w, b, f, H, T = ATRIUM_HALF_WIDTH, ATRIUM_BACK_Z, ATRIUM_FRONT_Z, ATRIUM_WALL_HEIGHT, ATRIUM_WALL
    y0, y1 = ATRIUM_SLAB
    sf = ATRIUM_SLAB_FRONT_Z
    e = 0.1  # walls reach this far into the ground slab; piers, beam and slab overlap likewise
    pier_outer = sf - ATRIUM_PIER_SETBACK       # the piers' faces towards the courtyard
    pier_inner = pier_outer - ATRIUM_PIER       # and towards the gallery
    nodes = [
        solid_node(g, "ground", box_solid((-w - T, -0.2, b - T), (w + T, 0.0, f + T)), ground),
        solid_node(g, "back wall", box_solid((-w - T, -e, b - T), (w + T, H, b)), stone),
        solid_node(g, "front wall", box_solid((-w - T, -e, f), (w + T, H, f + T)), stone),
        solid_node(g, "west wall", box_solid((-w - T, -e, b - T), (-w, H, f + T)), stone),
        solid_node(g, "east wall", box_solid((w, -e, b - T), (w + T, H, f + T)), stone),
        # The beam under the slab's front edge, recessed inside the piers' faces so no visible
        # faces are coplanar; it runs through the piers and into the side walls.
        solid_node(g, "beam", box_solid((-w - T / 2, ATRIUM_BEAM_BOTTOM, pier_inner + ATRIUM_BEAM_RECESS),
                                        (w + T / 2, y0 + 0.05, pier_outer - ATRIUM_BEAM_RECESS)), stone),
    ]
    # The upper slab reaches half the wall thickness into the back and side walls. Its top,
    # the terrace floor, is terracotta: the light it bounces onto the upper back wall is
    # orange, so light that leaks down through the slab is visibly orange.
    pos, nrm = box_solid((-w - T / 2, y0, b - T / 2), (w + T / 2, y1, sf))
    for name, top, mat in (("upper slab", False, stone), ("terrace floor", True, terracotta)):
        idx = [i for i in range(len(pos)) if (nrm[i][1] > 0.5) == top]
        nodes.append(solid_node(g, name, ([pos[i] for i in idx], [nrm[i] for i in idx]), mat))
    for i, x in enumerate(ATRIUM_PIER_XS):
        half = ATRIUM_PIER / 2
        nodes.append(solid_node(g, f"pier {i + 1}", box_solid((x - half, -e, pier_inner),
                                                               (x + half, y0 + 0.07, pier_outer)), stone))
    d = atrium_sun_direction()
    nodes.append(g.light("sun", {"name": "sun", "type": "directional", "color": ATRIUM_SUN_COLOR,
                                 "intensity": ATRIUM_SUN_INTENSITY}, rotation=quat_look(d)))
    if orbit:
        nodes.append(camera_node(g, "orbiting camera", atrium_orbit_path()[1][0], ATRIUM_ORBIT_PIVOT))
    else:
        nodes.append(camera_node(g, "gallery camera", ATRIUM_CAMERA, ATRIUM_CAMERA_TARGET))
    description = ("courtyard open to the sky; two-storey gallery along the back wall under a thin slab; "
                   "sun on the terrace and the upper back wall, camera in the ground-floor gallery")
    if pan:
        from .animated import camera_path
        camera_path(g, nodes[-1], "pan along the gallery", ATRIUM_PAN_TIMES, ATRIUM_PAN_EYES, ATRIUM_PAN_TARGETS)
        description += "; the camera walks along the gallery under the slab, turning out to the courtyard, over 4 s"
    if orbit:
        from .animated import camera_path
        camera_path(g, nodes[-1], "orbit across the courtyard", *atrium_orbit_path())
        description += "; the camera swings 160° on an arc across the courtyard and back in 4 s (80°/s)"
    name = "atrium pan" if pan else "atrium orbit" if orbit else "atrium"
    g.doc["scene"] = g.add("scenes", {"name": name, "nodes": nodes, "extras": {
        "description": description,
        "units": "m",
        "courtyard_min": vec((-w, 0.0, sf)),
        "courtyard_max": vec((w, H, f)),
        "ground_gallery_min": vec((-w, 0.0, b)),
        "ground_gallery_max": vec((w, y0, sf)),
        "slab_min": vec((-w, y0, b)),
        "slab_max": vec((w, y1, sf)),
        "slab_bottom_y": y0,
        "slab_top_y": y1,
        "slab_thickness": round(y1 - y0, 6),
        "back_wall_z": b,
        "wall_height": H,
        "shadowed_back_wall_min": vec((-w, 0.0, b)),
        "shadowed_back_wall_max": vec((w, y0, b)),
        "sunlit_back_wall_min": vec((-w, y1, b)),
        "sunlit_back_wall_max": vec((w, H, b)),
        "sun_direction": vec(d),
        "sun_elevation_degrees": ATRIUM_SUN_ELEVATION,
        "sun_azimuth_degrees": ATRIUM_SUN_AZIMUTH,
        "sun_irradiance_w_per_m2": ATRIUM_SUN_INTENSITY,
        "pier_inner_face_z": round(pier_inner, 6),
        "beam_inner_face_z": round(pier_inner + ATRIUM_BEAM_RECESS, 6),
        "beam_bottom_y": ATRIUM_BEAM_BOTTOM}})
    return gltf_text(g)
