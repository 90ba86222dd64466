#!/usr/bin/env python3
"""Cuts a glTF model down to its N triangles nearest a line through it.

For the real-mesh size series (papers/performance.md): cuts of one real
mesh at several sizes, each a connected-looking slab of the model around the
same line, so that larger cuts hold the smaller ones. The line runs through
the centre of the model's bounds along its longest horizontal axis (x or
z); a triangle's distance is its centroid's distance to the line.

Writes a self-contained .gltf (one mesh, one node, positions and indices
only, world coordinates; materials dropped: the cut is grey unless the
original had none either). Only triangle-list primitives of nodes with a
mesh are read; node transforms are applied.

Usage: python3 scripts/cut_mesh.py MODEL.glb|.gltf N OUT.gltf [--double-sided]
"""

import base64
import json
import math
import struct
import sys


def read_gltf(path):
    data = open(path, "rb").read()
    if data[:4] == b"glTF":
        length = struct.unpack_from("<I", data, 12)[0]
        doc = json.loads(data[20:20 + length])
        rest = data[20 + length:]
        binary = rest[8:8 + struct.unpack_from("<I", rest, 0)[0]] if rest else b""
        buffers = [binary]
    else:
        doc = json.loads(data)
        buffers = []
        base = path.rsplit("/", 1)[0] if "/" in path else "."
        for b in doc["buffers"]:
            uri = b["uri"]
            if uri.startswith("data:"):
                buffers.append(base64.b64decode(uri.split(",", 1)[1]))
            else:
                buffers.append(open(base + "/" + uri, "rb").read())
    return doc, buffers


def accessor(doc, buffers, index):
    a = doc["accessors"][index]
    view = doc["bufferViews"][a["bufferView"]]
    data = buffers[view["buffer"]]
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    comps = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    fmt, size = {5126: ("f", 4), 5125: ("I", 4), 5123: ("H", 2), 5121: ("B", 1)}[a["componentType"]]
    stride = view.get("byteStride", comps * size)
    out = []
    for i in range(a["count"]):
        out.append(struct.unpack_from("<" + fmt * comps, data, start + i * stride))
    return out


def matmul(a, b):
    return [sum(a[r + 4 * k] * b[k + 4 * c] for k in range(4)) for c in range(4) for r in range(4)]


def local_matrix(node):
    if "matrix" in node:
        return node["matrix"]
    t = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    s = node.get("scale", [1, 1, 1])
    r = [1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0,
         2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0,
         2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0,
         0, 0, 0, 1]
    m = [r[0] * s[0], r[1] * s[0], r[2] * s[0], 0, r[4] * s[1], r[5] * s[1], r[6] * s[1], 0,
         r[8] * s[2], r[9] * s[2], r[10] * s[2], 0, t[0], t[1], t[2], 1]
    return m


def triangles(doc, buffers):
    tris = []

    def visit(n, parent):
        node = doc["nodes"][n]
        m = matmul(parent, local_matrix(node))
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4:
                    continue
                pos = accessor(doc, buffers, prim["attributes"]["POSITION"])
                world = [(m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12],
                          m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13],
                          m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14]) for p in pos]
                idx = ([i[0] for i in accessor(doc, buffers, prim["indices"])]
                       if "indices" in prim else list(range(len(pos))))
                for t in range(0, len(idx) - 2, 3):
                    tris.append((world[idx[t]], world[idx[t + 1]], world[idx[t + 2]]))
        for c in node.get("children", []):
            visit(c, m)

    identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    scene = doc["scenes"][doc.get("scene", 0)]
    for n in scene["nodes"]:
        visit(n, identity)
    return tris


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    path, count, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    double_sided = "--double-sided" in sys.argv[4:]
    doc, buffers = read_gltf(path)
    tris = triangles(doc, buffers)
    lo = [min(v[k] for t in tris for v in t) for k in range(3)]
    hi = [max(v[k] for t in tris for v in t) for k in range(3)]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    axis = 0 if hi[0] - lo[0] >= hi[2] - lo[2] else 2

    def distance(t):
        c = [sum(v[k] for v in t) / 3 for k in range(3)]
        return math.hypot(*[c[k] - centre[k] for k in range(3) if k != axis])

    kept = sorted(tris, key=distance)[:count]
    # Shared corners stay shared (one index), so that the importer sees the
    # mesh's edges as the original has them.
    index_of = {}
    for t in kept:
        for v in t:
            index_of.setdefault(v, len(index_of))
    flat = list(index_of)
    positions = b"".join(struct.pack("<fff", *v) for v in flat)
    indices = b"".join(struct.pack("<I", index_of[v]) for t in kept for v in t)
    pmin = [min(v[k] for v in flat) for k in range(3)]
    pmax = [max(v[k] for v in flat) for k in range(3)]
    gltf = {
        "asset": {"version": "2.0", "generator": "radiosity scripts/cut_mesh.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "cut"}],
        "materials": [{"name": "grey", "doubleSided": double_sided,
                       "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1],
                                                "metallicFactor": 0}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1,
                                    "material": 0}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(flat),
                       "type": "VEC3", "min": pmin, "max": pmax},
                      {"bufferView": 1, "componentType": 5125, "count": 3 * len(kept),
                       "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteLength": len(positions)},
                        {"buffer": 0, "byteOffset": len(positions),
                         "byteLength": len(indices)}],
        "buffers": [{"byteLength": len(positions) + len(indices),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(positions + indices).decode()}],
    }
    with open(out, "w") as f:
        json.dump(gltf, f)
    print(f"{out}: {len(kept)} of {len(tris)} triangles, within "
          f"{distance(kept[-1]):.3f} of the line along axis {'xyz'[axis]}")


if __name__ == "__main__":
    main()
