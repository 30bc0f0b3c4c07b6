"""Write the seed corpus of brdf-fuzz (``corpus/<target>/``): small valid and near-valid files of each format.

Run from anywhere: ``python crates/brdf-fuzz/make_corpus.py``. The only mesh data that is not made up here is
an excerpt (the first 48 faces) of the Garland QSlim cow in ``tests/data/garland_cow.obj``, CC0-1.0 (see
``tests/data/README.md``). Small seeds keep every execution fast; the mutator supplies the hostile variety.
"""

from __future__ import annotations

import struct
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
OUT = HERE / "corpus"

CUBE_V = [(x, y, z) for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)]
CUBE_QUADS = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]


def cow_excerpt(faces: int = 48) -> tuple[list[tuple[float, ...]], list[tuple[int, ...]]]:
    lines = (ROOT / "tests" / "data" / "garland_cow.obj").read_text().splitlines()
    verts = [tuple(map(float, l.split()[1:4])) for l in lines if l.startswith("v ")]
    tris = [tuple(int(i) - 1 for i in l.split()[1:4]) for l in lines if l.startswith("f ")][:faces]
    used = sorted({i for t in tris for i in t})
    remap = {old: new for new, old in enumerate(used)}
    return [verts[i] for i in used], [tuple(remap[i] for i in t) for t in tris]


def obj_files() -> dict[str, str]:
    cv, cf = cow_excerpt()
    cow = "# excerpt of the Garland QSlim cow (CC0-1.0)\n"
    cow += "".join(f"v {x:.6g} {y:.6g} {z:.6g}\n" for x, y, z in cv)
    cow += "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in cf)
    cube = "o cube\nmtllib cube.mtl\nusemtl grey\n"
    cube += "".join(f"v {x} {y} {z}\n" for x, y, z in CUBE_V)
    cube += "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    cube += "".join(f"vn {n}\n" for n in ("-1 0 0", "1 0 0", "0 -1 0", "0 1 0", "0 0 -1", "0 0 1"))
    cube += "s 1\n"
    cube += "".join(
        "f " + " ".join(f"{v + 1}/{k + 1}/{i + 1}" for k, v in enumerate(q)) + "\n"
        for i, q in enumerate(CUBE_QUADS)
    )
    relative = "g tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -4//-1 -3//-1 -1//-1\nvn 0 0 1\n"
    colors = "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nv 0.5 1.5 0 0.5 0.5 0.5\n"
    colors += "f 1 2 3 4 5\nl 1 2\np 3\nf 1 2\n# comment\r\nf 1 3 \\\n 4\n"
    return {
        "cow_excerpt.obj": cow,
        "cube_uv_normals.obj": cube,
        "relative.obj": relative,
        "colors_polygon.obj": colors,
    }


def ply_header(fmt: str, nv: int, nf: int, vprops: list[str], list_type: str, extra: str = "") -> bytes:
    h = f"ply\nformat {fmt} 1.0\ncomment brdf-fuzz seed\nelement vertex {nv}\n"
    h += "".join(f"property {p}\n" for p in vprops)
    h += f"element face {nf}\nproperty {list_type}\n{extra}end_header\n"
    return h.encode()


def ply_files() -> dict[str, bytes]:
    cv, cf = cow_excerpt(24)
    out = {}
    props = ["float x", "float y", "float z"]
    body = b"".join(struct.pack("<3f", *v) for v in cv) + b"".join(struct.pack("<B3i", 3, *t) for t in cf)
    out["cow_le.ply"] = (
        ply_header("binary_little_endian", len(cv), len(cf), props, "list uchar int vertex_indices") + body
    )
    dprops = ["double x", "double y", "double z", "uchar red", "uchar green", "uchar blue"]
    body = b"".join(struct.pack(">3d3B", *v, 200, 100, 50) for v in CUBE_V)
    body += b"".join(struct.pack(">I4I", 4, *q) for q in CUBE_QUADS)
    out["cube_be_colors.ply"] = (
        ply_header("binary_big_endian", 8, 6, dprops, "list uint uint vertex_index") + body
    )
    nprops = [*props, "float nx", "float ny", "float nz", "float s", "float t"]
    text = ply_header(
        "ascii",
        4,
        2,
        nprops,
        "list uchar int vertex_indices",
        "element edge 1\nproperty int vertex1\nproperty int vertex2\n",
    )
    text += b"0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n3 0 1 2\n4 0 1 2 3\n0 1\n"
    out["quad_ascii_normals.ply"] = text
    text = ply_header("ascii", 3, 2, ["float x", "float y", "float z"], "list ushort short vertex_indices")
    text += b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n"
    out["tri_ascii_short.ply"] = text
    return out


def stl_files() -> dict[str, bytes]:
    cv, cf = cow_excerpt(12)
    tris = [[cv[i] for i in f] for f in cf]
    text = (
        "solid cow_excerpt\n"
        + "".join(
            "facet normal 0 0 0\n outer loop\n"
            + "".join(f"  vertex {x:.6g} {y:.6g} {z:.6g}\n" for x, y, z in t)
            + " endloop\nendfacet\n"
            for t in tris
        )
        + "endsolid cow_excerpt\n"
    )
    binary = b"\x00" * 80 + struct.pack("<I", len(tris))
    binary += b"".join(
        struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v) for v in t) + b"\x00\x00" for t in tris
    )
    return {"cow_ascii.stl": text.encode(), "cow_binary.stl": binary}


def merl(dims: tuple[int, int, int], value: float = 0.5) -> bytes:
    n = dims[0] * dims[1] * dims[2]
    vals = [value * (1 + (i % 7)) - (1.0 if i % 11 == 0 else 0.0) for i in range(3 * n)]
    return struct.pack("<3i", *dims) + struct.pack(f"<{3 * n}d", *vals)


def merl_files() -> dict[str, bytes]:
    return {
        "valid_2x2x2.binary": merl((2, 2, 2)),
        "valid_3x2x4.binary": merl((3, 2, 4), 120.0),
        "merl_header_truncated.binary": struct.pack("<3i", 90, 90, 180) + b"\x00" * 64,
    }


def mit_dat(dims: tuple[int, int, int, int], half: int = 0, value: float = 0.05) -> bytes:
    """A MIT CSAIL anisotropic .dat file from its published layout (brdf_core::measured::mit_dat): 16 int32,
    then float32 values channel by channel; every 13th value negative (no data)."""
    header = [*dims, 0, 0, 1, 0, 0, half, 3, 0, 0, 0, 0, 0]
    n = dims[0] * dims[1] * dims[2] * dims[3]
    vals = [-1.0 if i % 13 == 0 else value * (1 + (i % 5)) for i in range(3 * n)]
    return struct.pack("<16i", *header) + struct.pack(f"<{3 * n}f", *vals)


def mit_dat_files() -> dict[str, bytes]:
    return {
        "valid_2x2x3x4.dat": mit_dat((2, 2, 3, 4)),
        "valid_half_3x2x2x2.dat": mit_dat((3, 2, 2, 2), half=1, value=2.0),
        "valid_1x1x1x1.dat": mit_dat((1, 1, 1, 1)),
        "header_only_45x45x180x90.dat": struct.pack(
            "<16i", 45, 45, 180, 90, 0, 0, 1, 0, 0, 0, 3, 0, 0, 0, 0, 0
        ),
    }


def mesh_files() -> dict[str, bytes]:
    # The layout of targets.rs `MeshBytes`: counts, flags, positions, indices, normals, colors, transform.
    def mesh(
        verts: list[tuple[float, ...]], faces: list[tuple[int, ...]], flags: int, tail: bytes = b""
    ) -> bytes:
        body = b"".join(struct.pack("<3f", *v) for v in verts) + b"".join(
            struct.pack("<3I", *f) for f in faces
        )
        return bytes([len(verts), len(faces), flags]) + body + tail

    tri = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]
    normals = b"".join(struct.pack("<3f", 0, 0, 1) for _ in tri)
    colors = b"".join(struct.pack("<3f", 0.5, 0.2, 0.1) for _ in tri)
    scale = struct.pack("<16f", 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1)
    cube_faces = [(a, b, c) for q in CUBE_QUADS for (a, b, c) in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    return {
        "triangle.bin": mesh(tri, [(0, 1, 2)], 0),
        "triangle_normals_colors_transform.bin": mesh(
            tri, [(0, 1, 2), (2, 1, 0)], 0b1110, normals + colors + scale
        ),
        "cube_wrapped.bin": mesh(CUBE_V, cube_faces, 0b1001, scale),
    }


def _gltf_doc(with_extras: bool) -> tuple[dict[str, object], bytes]:
    """A glTF document (one triangle; with extras: a quad, a node hierarchy, a material, a camera and a
    KHR_lights_punctual light) and its one binary buffer."""
    pos = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)] + ([(1.0, 1.0, 0.0)] if with_extras else [])
    idx = [0, 1, 2] + ([2, 1, 3] if with_extras else [])
    nrm = [(0.0, 0.0, 1.0)] * len(pos)
    uv = [(p[0], p[1]) for p in pos]
    blobs = [
        struct.pack(f"<{len(idx)}H", *idx) + b"\0" * (-2 * len(idx) % 4),
        struct.pack(f"<{3 * len(pos)}f", *[c for p in pos for c in p]),
        struct.pack(f"<{3 * len(pos)}f", *[c for n in nrm for c in n]),
        struct.pack(f"<{2 * len(pos)}f", *[c for t in uv for c in t]),
    ]
    views, offset = [], 0
    for b in blobs:
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(b)})
        offset += len(b)
    n = len(pos)
    accessors = [
        {"bufferView": 0, "componentType": 5123, "count": len(idx), "type": "SCALAR"},
        {
            "bufferView": 1,
            "componentType": 5126,
            "count": n,
            "type": "VEC3",
            "min": [0, 0, 0],
            "max": [1, 1, 0],
        },
        {"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC3"},
        {"bufferView": 3, "componentType": 5126, "count": n, "type": "VEC2"},
    ]
    prim: dict[str, object] = {"attributes": {"POSITION": 1, "NORMAL": 2, "TEXCOORD_0": 3}, "indices": 0}
    doc: dict[str, object] = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": offset}],
        "bufferViews": views,
        "accessors": accessors,
        "meshes": [{"primitives": [prim]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    if with_extras:
        prim["material"] = 0
        doc["materials"] = [
            {
                "name": "red metal",
                "pbrMetallicRoughness": {
                    "baseColorFactor": [0.8, 0.1, 0.1, 1],
                    "metallicFactor": 0.7,
                    "roughnessFactor": 0.3,
                },
                "emissiveFactor": [0.1, 0.0, 0.0],
                "alphaMode": "MASK",
                "doubleSided": True,
            }
        ]
        doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100}}]
        doc["extensionsUsed"] = ["KHR_lights_punctual"]
        doc["extensions"] = {
            "KHR_lights_punctual": {
                "lights": [
                    {"type": "spot", "color": [1, 0.9, 0.8], "intensity": 5, "spot": {"outerConeAngle": 0.6}}
                ]
            }
        }
        doc["nodes"] = [
            {"children": [1, 2, 3], "rotation": [0, 0.3826834, 0, 0.9238795], "scale": [2, 2, 2]},
            {"mesh": 0, "translation": [0, 0, -1]},
            {"camera": 0, "translation": [0, 0, 4]},
            {
                "extensions": {"KHR_lights_punctual": {"light": 0}},
                "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 3, 0, 1],
            },
        ]
    return doc, b"".join(blobs)


def gltf_files() -> dict[str, bytes]:
    import base64
    import json

    out = {}
    for name, extras in (("triangle", False), ("scene", True)):
        doc, blob = _gltf_doc(extras)
        embedded = dict(
            doc,
            buffers=[
                {
                    "byteLength": len(blob),
                    "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode(),
                }
            ],
        )
        out[f"{name}.gltf"] = json.dumps(embedded).encode()
        js = json.dumps(doc).encode()
        js += b" " * (-len(js) % 4)
        blob += b"\0" * (-len(blob) % 4)
        body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(blob), 0x004E4942) + blob
        out[f"{name}.glb"] = struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body
    return out


def _rgbe(r: float, g: float, b: float) -> bytes:
    import math

    m = max(r, g, b)
    if m < 1e-32:
        return b"\0\0\0\0"
    f, e = math.frexp(m)
    s = f * 256.0 / m
    return bytes((int(r * s), int(g * s), int(b * s), e + 128))


def hdr_files() -> dict[str, bytes]:
    """Radiance RGBE: a flat 4x2 map (scanlines too short for run-length encoding), and a 16x3 map in the
    "new" run-length encoding (per channel, packets of literal bytes and runs)."""
    head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n"
    flat = b"".join(_rgbe(0.1 * x, 0.2 * y, 1.5) for y in range(2) for x in range(4))
    rle = b""
    for y in range(3):
        px = [_rgbe(0.05 * x, 0.5, 2.0 * y + 0.1) for x in range(16)]
        rle += bytes((2, 2, 0, 16))
        for c in range(4):
            ch = bytes(p[c] for p in px)
            if len(set(ch)) == 1:
                rle += bytes((128 + 16, ch[0]))  # one run of 16
            else:
                rle += bytes((8,)) + ch[:8] + bytes((8,)) + ch[8:]  # two literal packets
    return {"flat_4x2.hdr": head + b"-Y 2 +X 4\n" + flat, "rle_16x3.hdr": head + b"-Y 3 +X 16\n" + rle}


def exr_files() -> dict[str, bytes]:
    """OpenEXR through the OpenEXR package (a dev dependency): float and half RGB, two compressions."""
    import tempfile

    import numpy as np
    import OpenEXR

    out = {}
    for name, dtype, comp in (
        ("float_4x2_none.exr", np.float32, OpenEXR.NO_COMPRESSION),
        ("half_8x4_zip.exr", np.float16, OpenEXR.ZIP_COMPRESSION),
    ):
        h, w = (2, 4) if dtype is np.float32 else (4, 8)
        rgb = (np.arange(h * w * 3).reshape(h, w, 3) * 0.01).astype(dtype)
        with tempfile.TemporaryDirectory() as d:
            path = f"{d}/{name}"
            header = {"compression": comp, "type": OpenEXR.scanlineimage}
            with OpenEXR.File(header, {"RGB": rgb}) as f:
                f.write(path)
            out[name] = Path(path).read_bytes()
    return out


def main() -> None:
    for target, files in (
        ("obj", obj_files()),
        ("ply", ply_files()),
        ("stl", stl_files()),
        ("merl", merl_files()),
        ("mit_dat", mit_dat_files()),
        ("mesh", mesh_files()),
        ("gltf", gltf_files()),
        ("hdr", hdr_files()),
        ("exr", exr_files()),
    ):
        d = OUT / target
        d.mkdir(parents=True, exist_ok=True)
        for name, data in files.items():
            (d / name).write_bytes(data.encode() if isinstance(data, str) else data)
    print(f"wrote {sum(1 for _ in OUT.rglob('*.*'))} files under {OUT}")


if __name__ == "__main__":
    main()
