"""Sponza: add a sun and a camera (tools/gen-scenes --sponza)."""

import json
import math
from pathlib import Path

from .vecmath import normalize, sub
from .solids import quat_look


# The Khronos glTF Sponza (glTF-Sample-Models 2.0/Sponza/glTF/Sponza.gltf) has neither a light
# nor a camera, so leakless refuses it ("no light") and would frame it from outside. Its one
# node scales the Crytek Sponza geometry (x -1920.9..1799.9, y -126.4..1429.4,
# z -1182.8..1105.4 in the mesh) by 0.008, so world units span x -15.4..14.4, y -1.0..11.4,
# z -9.5..8.8 (29.8 long): the values below are in those world units. They are a starting
# point read off the file's accessor bounds (ground floor at y ≈ 0, first-floor gallery floor
# at y ≈ 3.3, columns at z ≈ ±1.5..2), not checked against a rendering: adjust with --eye,
# --target and --sun.
SPONZA_EYE = (8.0, 1.6, 3.3)
SPONZA_TARGET = (-4.0, 2.6, 3.8)
SPONZA_SUN = (45.0, 180.0)  # elevation, azimuth (degrees; azimuth from +z towards +x, 180 = the sun at -z)
SPONZA_SUN_INTENSITY = 3.0


def sun_direction(elevation, azimuth):
    """Direction sunlight travels for a sun `elevation` degrees high standing towards
    `azimuth` (degrees from +z towards +x)."""
    e, a = math.radians(elevation), math.radians(azimuth)
    return (-math.sin(a) * math.cos(e), -math.sin(e), -math.cos(a) * math.cos(e))


def light_gltf(path, eye, target, sun):
    """A copy of the .gltf at `path` with a directional sun and a 60° camera added as root
    nodes of its scene (world units), written beside it as NAME-leakless.gltf so that its
    relative buffer and image URIs still resolve. Returns the new file's path."""
    src = Path(path)
    doc = json.loads(src.read_text(encoding="utf-8"))
    used = doc.setdefault("extensionsUsed", [])
    if "KHR_lights_punctual" not in used:
        used.append("KHR_lights_punctual")
    lights = doc.setdefault("extensions", {}).setdefault("KHR_lights_punctual", {}).setdefault("lights", [])
    lights.append({"name": "leakless sun", "type": "directional", "color": [1.0, 0.93, 0.8],
                   "intensity": SPONZA_SUN_INTENSITY})
    cameras = doc.setdefault("cameras", [])
    cameras.insert(0, {"name": "leakless camera", "type": "perspective",
                       "perspective": {"yfov": math.radians(60.0), "znear": 0.05}})
    nodes = doc.setdefault("nodes", [])
    for node in nodes:  # cameras moved up by one: the new one is the first
        if "camera" in node:
            node["camera"] += 1
    nodes.append({"name": "leakless sun", "rotation": quat_look(sun_direction(*sun)),
                  "extensions": {"KHR_lights_punctual": {"light": len(lights) - 1}}})
    nodes.append({"name": "leakless camera", "camera": 0, "translation": list(eye),
                  "rotation": quat_look(normalize(sub(target, eye)))})
    scenes = doc.setdefault("scenes", [{"nodes": []}])
    scene = scenes[doc.get("scene", 0)]
    # Depth-first from the scene's first root: the camera first, so it is the one used.
    scene["nodes"] = [len(nodes) - 1, len(nodes) - 2] + scene.get("nodes", [])
    out = src.with_name(src.stem + "-leakless.gltf")
    out.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    return out
