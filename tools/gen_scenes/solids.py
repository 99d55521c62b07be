"""Leak scenes: helpers (closed solids, cameras, looking along a direction)."""

import math

from .vecmath import cross, dot, normalize, oriented_triangles, sub


def quat_look(forward, up=(0.0, 1.0, 0.0)):
    """glTF quaternion [x, y, z, w] turning a node's -Z onto `forward`, its +Y towards `up`
    (cameras look down -Z; spot and directional lights shine along -Z)."""
    back = normalize(tuple(-x for x in forward))
    if abs(dot(back, normalize(up))) > 0.9999:  # looking straight up or down: any up will do
        up = (0.0, 0.0, -1.0)
    right = normalize(cross(up, back))
    upv = cross(back, right)
    # Rotation matrix with columns right, up, back; m[row][col].
    m = [[right[0], upv[0], back[0]], [right[1], upv[1], back[1]], [right[2], upv[2], back[2]]]
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0:
        s = 2 * math.sqrt(trace + 1)
        q = ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4)
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = 2 * math.sqrt(1 + m[0][0] - m[1][1] - m[2][2])
        q = (s / 4, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s)
    elif m[1][1] > m[2][2]:
        s = 2 * math.sqrt(1 + m[1][1] - m[0][0] - m[2][2])
        q = ((m[0][1] + m[1][0]) / s, s / 4, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s)
    else:
        s = 2 * math.sqrt(1 + m[2][2] - m[0][0] - m[1][1])
        q = ((m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, s / 4, (m[1][0] - m[0][1]) / s)
    if q[3] < 0:
        q = tuple(-x for x in q)
    return [round(x, 12) + 0.0 for x in q]


def grid_solid(xs, ys, zs, filled=lambda i, j, k: True):
    """The boundary of a union of cells of the grid xs × ys × zs (increasing coordinates):
    one quad per face between a filled cell and an empty or outside one, normal pointing out
    of the solid. Every quad is a whole grid face, so neighbouring quads share their corners
    exactly (no T-junctions) and the surface is closed. A box is the one-cell case."""
    nx, ny, nz = len(xs) - 1, len(ys) - 1, len(zs) - 1
    full = lambda i, j, k: 0 <= i < nx and 0 <= j < ny and 0 <= k < nz and filled(i, j, k)
    positions, normals = [], []
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if not full(i, j, k):
                    continue
                x, y, z = (xs[i], xs[i + 1]), (ys[j], ys[j + 1]), (zs[k], zs[k + 1])
                centre = (sum(x) / 2, sum(y) / 2, sum(z) / 2)
                faces = []
                for side in (0, 1):
                    if not full(i + (1 if side else -1), j, k):
                        faces.append([(x[side], y[0], z[0]), (x[side], y[1], z[0]),
                                      (x[side], y[1], z[1]), (x[side], y[0], z[1])])
                    if not full(i, j + (1 if side else -1), k):
                        faces.append([(x[0], y[side], z[0]), (x[1], y[side], z[0]),
                                      (x[1], y[side], z[1]), (x[0], y[side], z[1])])
                    if not full(i, j, k + (1 if side else -1)):
                        faces.append([(x[0], y[0], z[side]), (x[1], y[0], z[side]),
                                      (x[1], y[1], z[side]), (x[0], y[1], z[side])])
                p, n = oriented_triangles(faces, False, centre)
                positions += p
                normals += n
    return positions, normals


def box_solid(lo, hi):
    """A closed box (6 quads, 12 triangles), normals outward."""
    return grid_solid((lo[0], hi[0]), (lo[1], hi[1]), (lo[2], hi[2]))


def solid_node(g, name, solid, material):
    pos, nrm = solid
    return g.add("nodes", {"name": name, "mesh": g.mesh(name, pos, nrm, material)})


def camera_node(g, name, eye, target, yfov_degrees=60.0, znear=0.02):
    cam = g.add("cameras", {"name": name, "type": "perspective",
                            "perspective": {"yfov": math.radians(yfov_degrees), "znear": znear}})
    forward = normalize(sub(target, eye))
    return g.add("nodes", {"name": "camera", "camera": cam, "translation": list(eye),
                           "rotation": quat_look(forward)})


def vec(v):
    """A JSON-friendly point (plain floats, no -0.0)."""
    return [float(x) + 0.0 for x in v]
