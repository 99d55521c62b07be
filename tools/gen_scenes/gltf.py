"""The glTF builder, and the .gltf / .glb / PNG bytes it writes."""

import base64
import json
import re
import struct
import zlib


GENERATOR = "leakless tools/gen-scenes"

FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963


class Gltf:
    """Accumulates a glTF document and its single binary buffer."""

    def __init__(self):
        self.doc = {"asset": {"version": "2.0", "generator": GENERATOR}}
        self.bin = bytearray()

    def add(self, key, obj):
        """Appends obj to the top-level array `key`; returns its index."""
        self.doc.setdefault(key, []).append(obj)
        return len(self.doc[key]) - 1

    def view(self, data, target=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target is not None:
            v["target"] = target
        self.bin += data
        return self.add("bufferViews", v)

    def accessor(self, rows, kind, component=FLOAT, target=ARRAY_BUFFER, minmax=False):
        """rows: list of tuples (or numbers for SCALAR)."""
        fmt = {FLOAT: "f", UBYTE: "B", USHORT: "H", UINT: "I"}[component]
        flat = [x for r in rows for x in (r if isinstance(r, (tuple, list)) else (r,))]
        view = self.view(struct.pack("<%d%s" % (len(flat), fmt), *flat), target)
        a = {"bufferView": view, "componentType": component, "count": len(rows), "type": kind}
        if minmax:
            n = len(flat) // len(rows)
            # glTF requires min/max on POSITION (and animation inputs); float32-rounded.
            f32 = lambda x: struct.unpack("<f", struct.pack("<f", x))[0]
            cols = [[f32(flat[i]) for i in range(k, len(flat), n)] for k in range(n)]
            a["min"] = [min(c) for c in cols]
            a["max"] = [max(c) for c in cols]
        return self.add("accessors", a)

    def mesh(self, name, positions, normals, material, uvs=None, indices=None):
        """normals None: no NORMAL attribute (glTF: the loader computes flat normals)."""
        attrs = {"POSITION": self.accessor(positions, "VEC3", minmax=True)}
        if normals is not None:
            attrs["NORMAL"] = self.accessor(normals, "VEC3")
        if uvs is not None:
            attrs["TEXCOORD_0"] = self.accessor(uvs, "VEC2")
        prim = {"attributes": attrs, "material": material}
        if indices is not None:
            comp = USHORT if len(positions) < 65536 else UINT
            prim["indices"] = self.accessor(indices, "SCALAR", comp, ELEMENT_ARRAY_BUFFER)
        return self.add("meshes", {"name": name, "primitives": [prim]})

    def material(self, name, rgb, **extra):
        # metallicFactor 0: a diffuse (dielectric) surface in any other viewer too.
        pbr = {"baseColorFactor": [*rgb, 1.0], "metallicFactor": 0.0}
        pbr.update(extra.pop("pbr", {}))
        return self.add("materials", {"name": name, "pbrMetallicRoughness": pbr,
                                      "doubleSided": True, **extra})

    def light(self, node_name, light, **node):
        self.doc.setdefault("extensions", {}).setdefault(
            "KHR_lights_punctual", {"lights": []})["lights"].append(light)
        index = len(self.doc["extensions"]["KHR_lights_punctual"]["lights"]) - 1
        used = self.doc.setdefault("extensionsUsed", [])
        if "KHR_lights_punctual" not in used:
            used.append("KHR_lights_punctual")
        return self.add("nodes", {"name": node_name,
                                  "extensions": {"KHR_lights_punctual": {"light": index}}, **node})

    def finish(self):
        """The document with its buffer declared (the caller chooses how to store it)."""
        while len(self.bin) % 4:
            self.bin.append(0)
        self.doc["buffers"] = [{"byteLength": len(self.bin)}]
        return self.doc, bytes(self.bin)


# Top-level keys in reading order: what the scene is first, raw data last.
KEY_ORDER = ["asset", "extensionsUsed", "extensions", "scene", "scenes", "nodes", "cameras", "meshes",
             "materials", "textures", "images", "samplers", "animations", "accessors", "bufferViews", "buffers"]


def readable_json(doc):
    doc = {k: doc[k] for k in sorted(doc, key=KEY_ORDER.index)}
    text = json.dumps(doc, indent=1)
    # Arrays of numbers on one line: vectors and quaternions stay legible.
    return re.sub(r"\[\s+([-+0-9.eE,\s]+?)\s+\]",
                  lambda m: "[" + ", ".join(x.strip() for x in m.group(1).split(",")) + "]", text)


def gltf_text(g):
    """.gltf with the buffer embedded as a base64 data URI; readable JSON."""
    doc, data = g.finish()
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + \
        base64.b64encode(data).decode("ascii")
    return (readable_json(doc) + "\n").encode()


def glb_bytes(g):
    doc, data = g.finish()
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    body = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(data), b"BIN\0") + data
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def png_rgba(width, height, texels):
    """A minimal 8-bit RGBA PNG (no filtering), texels row-major from the top."""
    raw = b"".join(b"\0" + bytes(c for t in texels[y * width:(y + 1) * width] for c in t)
                   for y in range(height))

    def chunk(kind, payload):
        return struct.pack(">I", len(payload)) + kind + payload + \
            struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF)

    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)) + \
        chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
