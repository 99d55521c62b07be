"""The table of files tools/gen-scenes writes, and its command line."""

import sys
from pathlib import Path

from .cornell import cornell_box
from .emissive import cornell_panel, doorway_panel, glowing_box, sealed_panel
from .sphere import sphere
from .fixtures import (
    MALFORMED, convex_ball, floor_light, no_light, occluder, spot_sun, textured, textured_quad,
)
from .rooms import doorway, two_rooms
from .atrium import atrium
from .basilica import basilica
from .stress import (
    PARTITION_SWEEP_MM, SEALED_QUADS_BIG, ball_at_partition, big_radius, camera_in_wall, coplanar, door_gap,
    far_degenerate, grazing_spot, hundred_lights, lattice, light_near_wall, partition_sweep, room_10km,
    room_1mm, sealed_quads,
)
from .animated import door, doorway_walk, light_drift, moving_light
from .sponza import SPONZA_EYE, SPONZA_SUN, SPONZA_TARGET, light_gltf


ROOT = Path(__file__).resolve().parent.parent.parent  # the repository (this is tools/gen_scenes/outputs.py)


def outputs():
    glb = textured()
    return {
        "scenes/cornell-box.gltf": cornell_box(),
        "scenes/cornell-panel.gltf": cornell_panel(),
        "scenes/sphere.gltf": sphere(),
        "scenes/two-rooms.gltf": two_rooms(),
        "scenes/doorway.gltf": doorway(),
        "scenes/doorway-panel.gltf": doorway_panel(),
        "scenes/atrium.gltf": atrium(),
        "scenes/door.gltf": door(),
        "scenes/moving-light.gltf": moving_light(),
        "scenes/motion/doorway-walk.gltf": doorway_walk(),
        "scenes/motion/atrium-pan.gltf": atrium(pan=True),
        "scenes/motion/atrium-orbit.gltf": atrium(orbit=True),
        "scenes/motion/light-drift.gltf": light_drift(),
        "scenes/basilica.glb": basilica(),
        "scenes/basilica-sealed.glb": basilica(sealed=True),
        "scenes/stress/sealed-quads.gltf": sealed_quads(),
        "scenes/stress/sealed-quads-x1000.gltf": sealed_quads(SEALED_QUADS_BIG),
        **{f"scenes/stress/partition-{mm}mm.gltf": partition_sweep(mm) for mm in PARTITION_SWEEP_MM},
        "scenes/stress/door-gap.gltf": door_gap(),
        "scenes/stress/light-near-wall.gltf": light_near_wall(camera_in_b=False),
        "scenes/stress/light-near-wall-dark.gltf": light_near_wall(camera_in_b=True),
        "scenes/stress/coplanar.gltf": coplanar(camera_in_b=False),
        "scenes/stress/coplanar-dark.gltf": coplanar(camera_in_b=True),
        "scenes/stress/lattice.gltf": lattice(),
        "scenes/stress/room-1mm.gltf": room_1mm(),
        "scenes/stress/room-10km.gltf": room_10km(),
        "scenes/stress/big-radius.gltf": big_radius(),
        "scenes/stress/camera-in-wall.gltf": camera_in_wall(),
        "scenes/stress/far-degenerate.gltf": far_degenerate(),
        "scenes/stress/hundred-lights.gltf": hundred_lights(),
        "scenes/stress/grazing-spot.gltf": grazing_spot(),
        "scenes/stress/sealed-panel.gltf": sealed_panel(),
        "tests/scenes/floor-light.gltf": floor_light(),
        "tests/scenes/glowing-box.gltf": glowing_box(),
        "tests/scenes/textured.glb": glb,
        "tests/scenes/textured-quad.gltf": textured_quad(),
        "tests/scenes/occluder.gltf": occluder(),
        "tests/scenes/convex-ball.gltf": convex_ball(),
        "tests/scenes/ball-at-partition.gltf": ball_at_partition(),
        "tests/scenes/spot-sun.gltf": spot_sun(),
        "tests/scenes/no-light.gltf": no_light(),
        "tests/scenes/malformed.gltf": MALFORMED,
        "tests/scenes/truncated.glb": glb[:len(glb) // 2],
    }


def parse_triple(text, n=3):
    values = [float(x) for x in text.split(",")]
    if len(values) != n:
        raise SystemExit(f"gen-scenes: expected {n} comma-separated numbers, got {text!r}")
    return tuple(values)


def main():
    args = sys.argv[1:]
    if "--sponza" in args:
        opts = dict(zip(args[::2], args[1::2]))
        out = light_gltf(opts["--sponza"],
                         parse_triple(opts["--eye"]) if "--eye" in opts else SPONZA_EYE,
                         parse_triple(opts["--target"]) if "--target" in opts else SPONZA_TARGET,
                         parse_triple(opts["--sun"], 2) if "--sun" in opts else SPONZA_SUN)
        print(f"wrote {out}")
        return
    if "--basilica" in args:
        opts = dict(zip(args[::2], args[1::2]))
        detail = float(opts["--basilica"])
        if not 0.0 < detail <= 100.0:
            raise SystemExit(f"gen-scenes: --basilica DETAIL must be in (0, 100], got {detail}")
        out = Path(opts.get("--out", f"basilica-{detail:g}.glb"))
        data = basilica(detail, sealed="--sealed" in args)
        out.write_bytes(data)
        print(f"wrote {out} ({len(data)} bytes)")
        return
    check = "--check" in sys.argv[1:]
    stale = []
    for rel, data in outputs().items():
        path = ROOT / rel
        if check:
            if not path.exists() or path.read_bytes() != data:
                stale.append(rel)
            continue
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
        print(f"wrote {rel} ({len(data)} bytes)")
    if stale:
        print("gen-scenes: out of date (run tools/gen-scenes): " + ", ".join(stale), file=sys.stderr)
        sys.exit(1)
