#!/usr/bin/env python3
"""Writes tests/data/gltf/relief_cube.gltf: a cube with an sRGB base colour texture (checker.png),
a normal map (domes_normal.png, no TANGENT: viewers generate MikkTSpace tangents) and an
occlusion map (domes_occlusion.png), everything embedded as data URIs. Run from the repository root."""
import base64
import json
import struct

faces = [  # normal, u axis, v axis (v up in the picture; glTF's v runs down, flipped below)
    ((1, 0, 0), (0, 0, -1), (0, 1, 0)), ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
    ((0, 1, 0), (1, 0, 0), (0, 0, -1)), ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    ((0, 0, 1), (1, 0, 0), (0, 1, 0)), ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
]
pos, nrm, uv, idx = [], [], [], []
for n, u, v in faces:
    base = len(pos)
    for su, sv in ((0, 0), (1, 0), (1, 1), (0, 1)):
        p = [0.5 * n[k] + (su - 0.5) * u[k] + (sv - 0.5) * v[k] for k in range(3)]
        pos.append(p)
        nrm.append(list(n))
        uv.append([su, 1.0 - sv])
    idx += [base, base + 1, base + 2, base, base + 2, base + 3]
blob = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<3f", *p) for p in nrm)
blob += b"".join(struct.pack("<2f", *t) for t in uv) + b"".join(struct.pack("<H", i) for i in idx)
n = len(pos)


def image(path):
    return {"uri": "data:image/png;base64," + base64.b64encode(open(path, "rb").read()).decode()}


doc = {
    "asset": {"version": "2.0", "generator": "tools/data/make_relief_gltf.py"},
    "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "rotation": [0.1, 0.3, 0.0, 0.9486833]}],
    "meshes": [{"name": "cube", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                                 "indices": 3, "material": 0}]}],
    "materials": [{"name": "tiles", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0,
                                                             "roughnessFactor": 0.4},
                   "normalTexture": {"index": 1, "scale": 1.0}, "occlusionTexture": {"index": 2, "strength": 1.0}}],
    "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}, {"source": 2, "sampler": 0}],
    "samplers": [{"magFilter": 9729, "minFilter": 9987}],
    "images": [image("tests/data/textures/checker.png"), image("tests/data/textures/domes_normal.png"),
               image("tests/data/textures/domes_occlusion.png")],
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * n}, {"buffer": 0, "byteOffset": 12 * n, "byteLength": 12 * n},
                    {"buffer": 0, "byteOffset": 24 * n, "byteLength": 8 * n}, {"buffer": 0, "byteOffset": 32 * n, "byteLength": 2 * len(idx)}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3", "min": [-0.5] * 3, "max": [0.5] * 3},
        {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5123, "count": len(idx), "type": "SCALAR"},
    ],
}
with open("tests/data/gltf/relief_cube.gltf", "w") as f:
    json.dump(doc, f, indent=1)
    f.write("\n")
