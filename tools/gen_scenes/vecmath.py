"""Vector math on tuples, quaternions, triangles facing a side."""

import math


def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def normalize(a):
    n = math.sqrt(dot(a, a))
    return tuple(x / n for x in a)


def quat_axis_angle(axis, degrees):
    """glTF quaternion [x, y, z, w]."""
    h = math.radians(degrees) / 2
    ax = normalize(axis)
    # "+ 0.0" turns -0.0 into 0.0 so the JSON reads cleanly.
    return [ax[0] * math.sin(h) + 0.0, ax[1] * math.sin(h) + 0.0, ax[2] * math.sin(h) + 0.0, math.cos(h)]


def oriented_triangles(quads, toward_inside, reference):
    """Splits quads into triangles with flat normals, counter-clockwise around the normal.

    The normal of each quad faces `reference` when toward_inside, away from it otherwise,
    so the winding is right whatever order the source data lists the corners in.
    """
    positions, normals = [], []
    for q in quads:
        for tri in ((q[0], q[1], q[2]), (q[0], q[2], q[3])):
            n = normalize(cross(sub(tri[1], tri[0]), sub(tri[2], tri[0])))
            centre = tuple(sum(c) / 3 for c in zip(*tri))
            facing = dot(n, sub(reference, centre)) > 0
            if facing != toward_inside:
                tri, n = (tri[0], tri[2], tri[1]), tuple(-x for x in n)
            positions += tri
            normals += [n] * 3
    return positions, normals
