"""Scenes lit by emissive geometry (area lights): the Cornell box with its ceiling panel, a
closed glowing box (analytic), and the sealed rooms lit by a panel against the partition."""

from .cornell import cornell_geometry
from .gltf import Gltf, gltf_text
from .rooms import ROOMS_HEIGHT, ROOMS_PARTITION, finish_scene, rooms_build
from .solids import camera_node
from .vecmath import oriented_triangles


def emissive_material(g, name, rgb, emission, strength, double_sided=False):
    """A diffuse material of albedo `rgb` that emits emission × strength (W/m²/sr)."""
    m = g.material(name, rgb, emissiveFactor=list(emission), doubleSided=double_sided)
    if strength != 1.0:
        g.doc["materials"][m]["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}
        used = g.doc.setdefault("extensionsUsed", [])
        if "KHR_materials_emissive_strength" not in used:
            used.append("KHR_materials_emissive_strength")
    return m


# The measured Cornell lamp: 130 × 105 mm (x 213..343, z 227..332 mm), here 1 mm below the
# 548.8 mm ceiling so that it never shares a plane with it, facing down (one-sided, as the
# lamp's diffuser). Radiance (W/m²/sr) warm white × 32: the floor below gets about
# Le·A/h² ≈ 1.4 W/m², as under the point-lit box's light.
CORNELL_PANEL_MM = [(213, 547.8, 227), (343, 547.8, 227), (343, 547.8, 332), (213, 547.8, 332)]
CORNELL_PANEL_EMISSION = (1.0, 0.8, 0.5)
CORNELL_PANEL_STRENGTH = 32.0


def cornell_panel():
    g = Gltf()
    nodes = cornell_geometry(g)
    lamp = emissive_material(g, "lamp", (0.78, 0.78, 0.78), CORNELL_PANEL_EMISSION, CORNELL_PANEL_STRENGTH)
    quad = [tuple(c / 1000 for c in p) for p in CORNELL_PANEL_MM]
    pos, nrm = oriented_triangles([quad], True, (0.278, 0.0, 0.28))  # facing the floor
    nodes.append(g.add("nodes", {"name": "ceiling panel", "mesh": g.mesh("ceiling panel", pos, nrm, lamp)}))
    g.doc["scene"] = g.add("scenes", {"name": "cornell box (ceiling panel)", "nodes": nodes, "extras": {
        "source": "Cornell Box Data, graphics.cornell.edu/online/box/data.html (mm -> m)",
        "panel_radiance_w_per_m2_sr": [c * CORNELL_PANEL_STRENGTH for c in CORNELL_PANEL_EMISSION]}})
    return gltf_text(g)


# A closed 1 m cube whose every inner face emits Le and reflects with albedo ρ: radiance is
# the same everywhere, L = Le·Σ_{k=0}^{B+1} ρ^k with B indirect bounces (emission, direct
# light, then one more reflection per bounce), Le / (1 − ρ) without a limit.
GLOWING_BOX_ALBEDO = 0.5
GLOWING_BOX_RADIANCE = 1.0


def glowing_box():
    g = Gltf()
    m = emissive_material(g, "glowing white", (GLOWING_BOX_ALBEDO,) * 3, (GLOWING_BOX_RADIANCE,) * 3, 1.0)
    c = [(x, y, z) for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)]
    faces = [[c[0], c[1], c[3], c[2]], [c[4], c[5], c[7], c[6]], [c[0], c[1], c[5], c[4]],
             [c[2], c[3], c[7], c[6]], [c[0], c[2], c[6], c[4]], [c[1], c[3], c[7], c[5]]]
    pos, nrm = oriented_triangles(faces, True, (0.5, 0.5, 0.5))  # emitting inward
    nodes = [g.add("nodes", {"name": "box", "mesh": g.mesh("box", pos, nrm, m)}),
             camera_node(g, "inside", (0.5, 0.5, 0.15), (0.55, 0.45, 1.0), yfov_degrees=70.0)]
    g.doc["scene"] = g.add("scenes", {"name": "glowing box", "nodes": nodes, "extras": {
        "description": "closed cube, every inner face emits Le and reflects ρ: radiance Le·Σρ^k",
        "albedo": GLOWING_BOX_ALBEDO, "emitted_radiance": GLOWING_BOX_RADIANCE}})
    return gltf_text(g)


# The sealed two rooms lit only by a two-sided panel 1 mm in front of the partition's room-A
# face (the panel's back, facing the partition, emits too): room B must stay exactly black.
PANEL_GAP = 0.001


def sealed_panel():
    g, nodes, extras = rooms_build(False, light=None)
    lamp = emissive_material(g, "panel", (0.7, 0.7, 0.7), (1.0, 1.0, 1.0), 8.0, double_sided=True)
    x = -ROOMS_PARTITION / 2 - PANEL_GAP
    quad = [(x, 0.8, -0.6), (x, 1.6, -0.6), (x, 1.6, 0.6), (x, 0.8, 0.6)]
    pos, nrm = oriented_triangles([quad], True, (-1.0, 1.2, 0.0))
    nodes.append(g.add("nodes", {"name": "panel", "mesh": g.mesh("panel", pos, nrm, lamp)}))
    extras["description"] = ("two rooms sealed by a 2 cm partition, lit only by a two-sided emissive panel "
                             "1 mm from the partition in room A: room B gets no light")
    del extras["light_intensity_w_per_sr"]
    return finish_scene(g, "sealed panel", nodes, extras)


# The doorway scene lit only by a ceiling panel in room A, tessellated into 16 × 8 quads (256
# emitting triangles, as an exporter writes a subdivided light): room B, where the camera is,
# gets its light through the door. Radiance 8 W/m²/sr over 1.2 m × 0.8 m: about the 25 W the
# doorway's point light emits.
DOORWAY_PANEL = (-1.5, 0.3)   # centre (x, z) of the panel in room A
DOORWAY_PANEL_SIZE = (1.2, 0.8)
DOORWAY_PANEL_GRID = (16, 8)
DOORWAY_PANEL_RADIANCE = 8.0


def doorway_panel():
    g, nodes, extras = rooms_build(True, light=None)
    lamp = emissive_material(g, "ceiling panel", (0.8, 0.8, 0.8), (1.0, 1.0, 1.0), DOORWAY_PANEL_RADIANCE)
    y = ROOMS_HEIGHT - 0.001
    (cx, cz), (sx, sz), (nx, nz) = DOORWAY_PANEL, DOORWAY_PANEL_SIZE, DOORWAY_PANEL_GRID
    quads = []
    for i in range(nx):
        for j in range(nz):
            x0, x1 = cx - sx / 2 + sx * i / nx, cx - sx / 2 + sx * (i + 1) / nx
            z0, z1 = cz - sz / 2 + sz * j / nz, cz - sz / 2 + sz * (j + 1) / nz
            quads.append([(x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)])
    pos, nrm = oriented_triangles(quads, True, (cx, 0.0, cz))  # facing the floor
    nodes.append(g.add("nodes", {"name": "ceiling panel", "mesh": g.mesh("ceiling panel", pos, nrm, lamp)}))
    extras["description"] = ("the doorway rooms lit only by a ceiling panel of 256 emitting triangles in room A; "
                             "room B sees its light through the door")
    extras["panel_triangles"] = 2 * nx * nz
    del extras["light_intensity_w_per_sr"]
    return finish_scene(g, "doorway (ceiling panel)", nodes, extras)
