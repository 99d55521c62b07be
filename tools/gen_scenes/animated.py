"""Animated scenes (scenes/door.gltf, scenes/moving-light.gltf, scenes/motion/*.gltf) and the
camera animations of the motion benchmark."""

from .vecmath import normalize, quat_axis_angle, sub
from .solids import box_solid, quat_look, vec
from .rooms import ROOMS_LIGHT, ROOMS_PARTITION, finish_scene, rooms_build
from .stress import (
    DOOR_CLOSED_TIME, DOOR_COLOR, DOOR_LEAF_FOOT, DOOR_LEAF_INSET, DOOR_LEAF_OVERLAP, DOOR_LEAF_THICKNESS,
    DOOR_OPEN_DEGREES, EXPECT_LEAKS, EXPECT_LIT, EXPECT_MATCH, door_hinge, door_leaf_local, door_leaf_world,
    r6, restyle, room_b_not_dark, sealed_expectations,
)


def door():
    """doorway.gltf plus the door leaf (see DOOR_LEAF_*), hinged at the jamb at z = 0.35 and
    animated from open (90° into room A, t = 0) to closed (t = 2 s, then it stays closed);
    a handle (CUBICSPLINE rotation) and a bolt (STEP scale) ride on it."""
    g, nodes, extras = rooms_build(door=True)
    wood = g.material("door", DOOR_COLOR)
    steel = g.material("steel", (0.35, 0.35, 0.35))
    lo, hi = door_leaf_local(DOOR_LEAF_FOOT)
    T = DOOR_LEAF_THICKNESS
    handle = g.add("nodes", {"name": "door handle", "translation": [r6(-T - 0.01), 1.0, 0.8], "mesh": g.mesh(
        "door handle", *box_solid((-0.01, -0.01, -0.12), (0.015, 0.01, 0.01)), steel)})
    bolt = g.add("nodes", {"name": "door bolt", "translation": [-0.02, 1.0, hi[2]], "mesh": g.mesh(
        "door bolt", *box_solid((-0.005, -0.01, -0.01), (0.005, 0.01, 0.01)), steel)})
    q_open = quat_axis_angle((0.0, 1.0, 0.0), DOOR_OPEN_DEGREES)
    identity = (0.0, 0.0, 0.0, 1.0)
    leaf = g.add("nodes", {"name": "door leaf", "translation": list(door_hinge()), "rotation": q_open,
                           "mesh": g.mesh("door leaf", *box_solid(lo, hi), wood), "children": [handle, bolt]})
    nodes.insert(-2, leaf)
    key = lambda times: g.accessor(list(times), "SCALAR", target=None, minmax=True)
    out = lambda rows, kind: g.accessor([tuple(r) for r in rows], kind, target=None)
    zero = (0.0, 0.0, 0.0, 0.0)
    down = quat_axis_angle((1.0, 0.0, 0.0), -30.0)
    handle_times = (DOOR_CLOSED_TIME - 0.4, DOOR_CLOSED_TIME - 0.2, DOOR_CLOSED_TIME)
    samplers = [
        # The leaf: open to closed, slerp, constant angular speed.
        {"input": key((0.0, DOOR_CLOSED_TIME)), "output": out([q_open, identity], "VEC4"), "interpolation": "LINEAR"},
        # The handle turns down 30° and back as the door shuts (in-tangent, value, out-tangent).
        {"input": key(handle_times), "output": out([zero, identity, zero, zero, down, zero, zero, identity, zero],
                                                   "VEC4"), "interpolation": "CUBICSPLINE"},
        # The bolt shoots out (three times as long along the leaf's width) when the door is shut.
        {"input": key((0.0, DOOR_CLOSED_TIME)), "output": out([(1.0, 1.0, 1.0), (1.0, 1.0, 3.0)], "VEC3"),
         "interpolation": "STEP"},
    ]
    channels = [{"sampler": 0, "target": {"node": leaf, "path": "rotation"}},
                {"sampler": 1, "target": {"node": handle, "path": "rotation"}},
                {"sampler": 2, "target": {"node": bolt, "path": "scale"}}]
    g.add("animations", {"name": "door closes", "channels": channels, "samplers": samplers})
    closed_lo, closed_hi = door_leaf_world(DOOR_LEAF_FOOT)
    extras = restyle(
        extras, "a door swings shut (open at t = 0, closed from t = 2 s): room B is lit, then sealed by the "
                "leaf overlapping the partition and the floor slab; once closed, room B must go exactly black",
        open_time=0.0,
        closed_time=DOOR_CLOSED_TIME,
        hinge=vec(door_hinge()),
        hinge_axis=[0.0, 1.0, 0.0],
        open_angle_degrees=DOOR_OPEN_DEGREES,
        leaf_size=[T, r6(hi[1] - lo[1]), hi[2]],
        leaf_closed_min=vec(closed_lo),
        leaf_closed_max=vec(closed_hi),
        leaf_overlap=DOOR_LEAF_OVERLAP,
        leaf_inset=DOOR_LEAF_INSET,
        dark_min=extras["dark_room_min"],
        dark_max=extras["dark_room_max"],
        expected=sealed_expectations())
    return finish_scene(g, "door", nodes, extras)


def light_path(g, light, name, times, positions):
    """Animates node `light` through `positions` at `times` (LINEAR translation)."""
    key = g.accessor(list(times), "SCALAR", target=None, minmax=True)
    where = g.accessor([tuple(p) for p in positions], "VEC3", target=None)
    g.add("animations", {"name": name,
                         "channels": [{"sampler": 0, "target": {"node": light, "path": "translation"}}],
                         "samplers": [{"input": key, "output": where, "interpolation": "LINEAR"}]})


# moving-light: doorway.gltf (at t = 0 the same scene) with its light walking through the door:
# room A at t = 0, the middle of the doorway at t = 2 s, room B at t = 4 s (LINEAR in between).
MOVING_LIGHT_TIMES = (0.0, 2.0, 4.0)
MOVING_LIGHT_PATH = (ROOMS_LIGHT, (0.0, 1.0, 0.75), (1.2, 1.8, 0.3))


def moving_light():
    g, nodes, extras = rooms_build(door=True)
    light_path(g, nodes[-2], "light walks through the door", MOVING_LIGHT_TIMES, MOVING_LIGHT_PATH)
    t = ROOMS_PARTITION / 2
    (t0, t1, t2), (p0, p1, p2) = MOVING_LIGHT_TIMES, MOVING_LIGHT_PATH
    enters = t0 + (t1 - t0) * (-t - p0[0]) / (p1[0] - p0[0])   # crosses x = -t (room A's side)
    leaves = t1 + (t2 - t1) * (t - p1[0]) / (p2[0] - p1[0])    # crosses x = +t (room B's side)
    extras = restyle(
        extras, "a point light moving from room A through the doorway into room B over 4 s (translation, LINEAR); "
                "at t = 0 the scene is doorway.gltf",
        light_times=list(MOVING_LIGHT_TIMES),
        light_positions=[vec(p) for p in MOVING_LIGHT_PATH],
        light_enters_doorway_time=r6(enters),
        light_leaves_doorway_time=r6(leaves),
        same_at_time_0="scenes/doorway.gltf",
        expected={"direct": EXPECT_LIT, "reference": EXPECT_LIT, "splat": EXPECT_LEAKS,
                  "leakless": EXPECT_MATCH, "leakless-capped": EXPECT_LIT})
    return finish_scene(g, "moving light", nodes, room_b_not_dark(extras, room_a_lit=False))


def camera_path(g, camera, name, times, eyes, targets):
    """Animates node `camera` through `eyes` looking at `targets` at `times` (LINEAR
    translation and slerped rotation)."""
    key = g.accessor(list(times), "SCALAR", target=None, minmax=True)
    where = g.accessor([tuple(e) for e in eyes], "VEC3", target=None)
    look = g.accessor([tuple(quat_look(normalize(sub(t, e)))) for e, t in zip(eyes, targets)], "VEC4", target=None)
    g.add("animations", {"name": name, "samplers": [
        {"input": key, "output": where, "interpolation": "LINEAR"},
        {"input": key, "output": look, "interpolation": "LINEAR"},
    ], "channels": [{"sampler": 0, "target": {"node": camera, "path": "translation"}},
                    {"sampler": 1, "target": {"node": camera, "path": "rotation"}}]})


# doorway-walk: doorway.gltf with the camera walking from room A through the door (t = 2 s)
# into room B, turning right there to look into it (t = 4 s).
WALK_TIMES = (0.0, 2.0, 4.0)
WALK_EYES = ((-2.2, 1.5, 0.75), (-0.2, 1.5, 0.75), (1.2, 1.5, 0.6))
WALK_TARGETS = ((0.0, 1.2, 0.75), (2.0, 1.2, 0.75), (2.8, 1.2, -1.5))


def doorway_walk():
    g, nodes, extras = rooms_build(door=True, eye=WALK_EYES[0], target=WALK_TARGETS[0], camera_name="walking camera")
    camera_path(g, nodes[-1], "walk through the door", WALK_TIMES, WALK_EYES, WALK_TARGETS)
    extras = restyle(
        extras, "doorway.gltf with the camera walking from room A through the door into room B over 4 s, "
                "turning to look into room B (the motion benchmark's walk)",
        walk_times=list(WALK_TIMES),
        walk_eyes=[vec(e) for e in WALK_EYES],
        expected={"direct": EXPECT_LIT, "reference": EXPECT_LIT, "splat": EXPECT_LEAKS,
                  "leakless": EXPECT_MATCH, "leakless-capped": EXPECT_LIT})
    return finish_scene(g, "doorway walk", nodes, room_b_not_dark(extras, room_a_lit=True))


# light-drift: doorway.gltf with the camera still in room B and the light drifting slowly in
# room A, 0.25 m/s along -z (1 m over 4 s, LINEAR): what room B sees through the door changes
# slowly, which shows temporal reuse's lag. At t = 0 the scene is doorway.gltf.
DRIFT_TIMES = (0.0, 4.0)
DRIFT_PATH = (ROOMS_LIGHT, (ROOMS_LIGHT[0], ROOMS_LIGHT[1], ROOMS_LIGHT[2] - 1.0))


def light_drift():
    g, nodes, extras = rooms_build(door=True)
    light_path(g, nodes[-2], "light drifts in room A", DRIFT_TIMES, DRIFT_PATH)
    extras = restyle(
        extras, "doorway.gltf with the camera still in room B and the point light drifting 1 m along -z in "
                "room A over 4 s (0.25 m/s; the motion benchmark's slow light)",
        light_times=list(DRIFT_TIMES),
        light_positions=[vec(p) for p in DRIFT_PATH],
        same_at_time_0="scenes/doorway.gltf",
        expected={"direct": EXPECT_LIT, "reference": EXPECT_LIT, "splat": EXPECT_LEAKS,
                  "leakless": EXPECT_MATCH, "leakless-capped": EXPECT_LIT})
    return finish_scene(g, "light drift", nodes, room_b_not_dark(extras, room_a_lit=True))
