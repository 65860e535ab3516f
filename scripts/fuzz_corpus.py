#!/usr/bin/env python3
"""Writes the seed corpora of the file-format fuzz targets (fuzz/corpus/{mesh,scene,bsdf,
coefficients,basis}): small valid files of each format, and a few near misses, a few KB each.
(Inputs the fuzzers found, such as coefficients/float-offset-finding.safetensors, are committed
beside them as they were found.)

    scripts/fuzz_corpus.py [OUTPUT_DIR]   (default: fuzz/corpus beside this script)

Standard library only; the formats are written from their descriptions in src/ (mesh_io.h,
scene_spec.h, tensor_file.h and rgl_bsdf.h, coefficient_file.h, image_basis.h, gi_basis.h,
safetensors.h), so that the corpus does not depend on a build.
"""
import base64
import json
import math
import os
import struct
import sys


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


# --- meshes -------------------------------------------------------------------------------------

def quad_bin():
    positions = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
    indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    return positions + indices  # 60 bytes


def quad_gltf(buffer_uri=None, nodes=None):
    buffer = {"byteLength": len(quad_bin())}
    if buffer_uri:
        buffer["uri"] = buffer_uri
    return {
        "asset": {"version": "2.0"},
        "buffers": [buffer],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": nodes or [{"mesh": 0, "translation": [0, 0, 5], "scale": [2, 2, 2]}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }


def glb(gltf, binary):
    binary += b"\0" * (-len(binary) % 4)
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(binary)
    return (b"glTF" + struct.pack("<II", 2, total) + struct.pack("<I", len(text)) + b"JSON" + text +
            struct.pack("<I", len(binary)) + b"BIN\0" + binary)


def meshes(out):
    data_uri = "data:application/octet-stream;base64," + base64.b64encode(quad_bin()).decode()
    write(f"{out}/mesh/quad.gltf", json.dumps(quad_gltf(data_uri)))
    write(f"{out}/mesh/quad.glb", glb(quad_gltf(), quad_bin()))
    shared = [{"children": [i + 1, i + 1]} for i in range(4)] + [{"mesh": 0, "rotation": [0, 0.6, 0, 0.8]}]
    write(f"{out}/mesh/shared-children.glb", glb(quad_gltf(nodes=shared), quad_bin()))
    matrix = [{"mesh": 0, "matrix": [2, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 1, 2, 3, 1], "children": [1]},
              {"mesh": 0, "scale": [-1, 1, 1]}]
    write(f"{out}/mesh/matrix-and-mirror.glb", glb(quad_gltf(nodes=matrix), quad_bin()))
    normals = quad_gltf()
    normals["bufferViews"].append({"buffer": 0, "byteOffset": 0, "byteLength": 48})
    normals["accessors"].append({"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3"})
    normals["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 2
    normals["meshes"][0]["primitives"].append({"attributes": {"POSITION": 0}})  # no indices
    write(f"{out}/mesh/normals-no-indices.glb", glb(normals, quad_bin()))
    write(f"{out}/mesh/quad.obj", "# quad and triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                  "vn 0 0 1\nvn 0 0.6 0.8\nf 1//1 2//1 3//2 4//2\nv 0 0 1\nf -1 1/7 2//1\n")
    write(f"{out}/mesh/tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")


# --- scenes -------------------------------------------------------------------------------------

def scenes(out):
    box = {
        "name": "box",
        "camera": {"position": [0, 2, 3.9], "target": [0, 1.8, 0], "fov": 55},
        "environment": {"constant": [0.1, 0.1, 0.1], "rotation": 90, "intensity": 0.5},
        "objects": [
            {"shape": "sphere", "center": [0, 1, -0.3], "radius": 1, "material": {"type": "measured"}},
            {"shape": "quad", "corner": [-2, 0, -2], "edge1": [0, 0, 6], "edge2": [4, 0, 0],
             "material": {"type": "ggx", "albedo": [0.7, 0.7, 0.7], "specular": [0.04, 0.04, 0.04], "alpha": 0.1}},
            {"shape": "quad", "corner": [-0.8, 3.99, -1.1], "edge1": [1.6, 0, 0], "edge2": [0, 0, 1.6],
             "emission": [8, 6.8, 5.1]},
        ],
    }
    write(f"{out}/scene/box.json", json.dumps(box, indent=1))
    mesh = {"objects": [{"shape": "mesh", "mesh": "sphere", "center": [0, 5, 0], "rest_on": 0.25,
                         "rotate_y": 30, "material": {"type": "lambert", "albedo": [0.5, 0.4, 0.3]}}]}
    write(f"{out}/scene/mesh.json", json.dumps(mesh))
    # The fuzz target reads what follows a NUL byte as the mesh file of objects named "$mesh".
    with_mesh = {"camera": {"position": [0, 0, 4]},
                 "objects": [{"shape": "mesh", "mesh": "$mesh", "radius": 0.5, "material": {"type": "measured"}}]}
    write(f"{out}/scene/with-obj.json", json.dumps(with_mesh) + "\0" +
          "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    write(f"{out}/scene/far-camera.json", json.dumps({"camera": {"position": [1e308, 0, 0]},
                                                      "objects": [{"shape": "sphere"}]}))


# --- RGL tensor files ---------------------------------------------------------------------------

F32, U8 = 10, 1


def tensor_file(fields):
    """fields: (name, dtype code, shape, bytes); data 8-byte aligned after the header."""
    header = 12 + 2 + 4 + sum(2 + len(n) + 2 + 1 + 8 + 8 * len(s) for n, _, s, _ in fields)
    offsets, end = [], (header + 7) // 8 * 8
    for _, _, _, data in fields:
        offsets.append(end)
        end = (end + len(data) + 7) // 8 * 8
    out = bytearray(end)
    pos = 0

    def put(b):
        nonlocal pos
        out[pos:pos + len(b)] = b
        pos += len(b)

    put(b"tensor_file\0" + bytes([1, 0]) + struct.pack("<I", len(fields)))
    for (name, dtype, shape, _), offset in zip(fields, offsets):
        put(struct.pack("<H", len(name)) + name.encode() + struct.pack("<HBQ", len(shape), dtype, offset))
        put(struct.pack(f"<{len(shape)}Q", *shape))
    for (_, _, _, data), offset in zip(fields, offsets):
        out[offset:offset + len(data)] = data
    return bytes(out)


def f32(name, shape, values):
    return (name, F32, shape, struct.pack(f"<{len(values)}f", *values))


def synthetic_rgl(theta_i=(0.0, 0.6, 1.2, 1.5707964), phi_i=(0.0,), vndf_res=4, refl_res=3, wavelengths=None,
                  jacobian=1):
    """The material of tests/support/synthetic_rgl.h, smaller."""
    np_, nt = len(phi_i), len(theta_i)
    text = b"synthetic fuzz seed"
    fields = [("description", U8, [len(text)], text), f32("phi_i", [np_], phi_i), f32("theta_i", [nt], theta_i)]
    fields.append(f32("sigma", [2, 4], [0.5 + 0.25 * x / 3 for _ in range(2) for x in range(4)]))
    fields.append(f32("ndf", [2, 4], [1 + x / 3 for _ in range(2) for x in range(4)]))
    fields.append(f32("vndf", [np_, nt, vndf_res, vndf_res], [1.0] * (np_ * nt * vndf_res * vndf_res)))
    channels = len(wavelengths) if wavelengths else 3
    refl = []
    for p in range(np_):
        for t in range(nt):
            for c in range(channels):
                for y in range(refl_res):
                    for x in range(refl_res):
                        u, v = x / (refl_res - 1), y / (refl_res - 1)
                        refl.append((1 + theta_i[t]) * (0.2 + 0.1 * (c % 3) + 0.3 * u + 0.1 * v + 0.2 * u * v))
    shape = [np_, nt, channels, refl_res, refl_res]
    if wavelengths:
        fields.append(f32("wavelengths", [channels], wavelengths))
        fields.append(f32("spectra", shape, refl))
    else:
        fields.append(f32("rgb", shape, refl))
    fields.append(("jacobian", U8, [1], bytes([jacobian])))
    return tensor_file(fields)


def bsdfs(out):
    write(f"{out}/bsdf/rgb.bsdf", synthetic_rgl())
    write(f"{out}/bsdf/spectral.bsdf", synthetic_rgl(wavelengths=[400, 500, 600, 700], jacobian=0))
    write(f"{out}/bsdf/anisotropic.bsdf", synthetic_rgl(theta_i=(0.0, 1.0), phi_i=(-math.pi, 0.0, math.pi),
                                                         vndf_res=3, refl_res=2))
    write(f"{out}/bsdf/fields.bsdf", tensor_file([("a", 3, [2, 2], struct.pack("<4H", 1, 2, 3, 4)),
                                                  ("b", 11, [1], struct.pack("<d", 0.5)), ("empty", U8, [0], b"")]))


# --- safetensors files --------------------------------------------------------------------------

SIZES = {"F64": 8, "F32": 4, "F16": 2, "I32": 4, "I64": 8, "U8": 1}
PACK = {"F64": "d", "F32": "f", "F16": "e", "I32": "i", "I64": "q", "U8": "B"}


def safetensors(metadata, tensors):
    """tensors: (name, dtype, shape, values), written by decreasing element size."""
    tensors = sorted(tensors, key=lambda t: -SIZES[t[1]])
    header, data = {"__metadata__": metadata}, b""
    for name, dtype, shape, values in tensors:
        blob = struct.pack(f"<{len(values)}{PACK[dtype]}", *values)
        header[name] = {"dtype": dtype, "shape": shape, "data_offsets": [len(data), len(data) + len(blob)]}
        data += blob
    text = json.dumps(header, separators=(",", ":")).encode()
    text += b" " * (-(8 + len(text)) % 64)
    return struct.pack("<Q", len(text)) + text + data


def coefficient_files(out):
    bands, t_count = 2, 3
    k = (bands + 1) * (bands + 2) // 2
    names = ["red", "blue"]
    meta = {"format": "matlas-zonal", "version": "1", "bands": str(bands), "theta_o_count": str(t_count),
            "theta_rows": "8", "phi_columns": "16", "names": json.dumps(names), "storage": "f32",
            "storage_error": "0"}
    per = t_count * k * 3
    coeffs = [0.01 * i for i in range(len(names) * per)]
    common = [("alpha", "F32", [k], [0.1 * j for j in range(k)]),
              ("band", "I32", [k], [int(math.isqrt(2 * j)) for j in range(k)]),
              ("theta_o", "F32", [t_count], [(t + 0.5) * math.pi / 2 / t_count for t in range(t_count)])]
    write(f"{out}/coefficients/f32.safetensors",
          safetensors(meta, [("coefficients", "F32", [len(names), t_count, k, 3], coeffs)] + common))
    meta16 = dict(meta, storage="f16", source_key="fuzz")
    write(f"{out}/coefficients/f16-mean.safetensors",
          safetensors(meta16, [("coefficients", "F16", [len(names), t_count, k, 3], coeffs),
                               ("mean", "F16", [t_count, k, 3], coeffs[:per])] + common))


def basis_files(out):
    w, h, n = 4, 3, 2
    pixels = h * w * 3
    mean = [0.1 + 0.01 * i for i in range(pixels)]
    images = [0.5 if (i // 3) % 2 else 0.1 + 0.01 * (i % pixels) for i in range(n * pixels)]  # half the pixels vary
    meta = {"format": "matlas-image-basis", "width": str(w), "height": str(h), "count": str(n),
            "names": json.dumps(["a", "b"])}
    write(f"{out}/basis/image-f32.safetensors",
          safetensors(meta, [("mean", "F32", [h, w, 3], mean), ("images", "F32", [n, h, w, 3], images)]))
    write(f"{out}/basis/image-f16-lowrank.safetensors",
          safetensors(dict(meta, lowrank_relative_error="0.01"),
                      [("mean", "F32", [h, w, 3], mean), ("images", "F16", [n, h, w, 3], images),
                       ("lowrank_factors", "F32", [1, h, w, 3], images[:pixels]),
                       ("lowrank_coefficients", "F64", [n, 1], [0.5, -0.5])]))
    gi_meta = {"format": "matlas-gi-basis", "names": json.dumps(["a", "b"]), "key": "{}"}
    write(f"{out}/basis/gi.safetensors",
          safetensors(gi_meta, [("p", "F32", [h, w, 3], mean), ("linear", "F32", [n + 1, h, w, 3], mean * (n + 1)),
                                ("full", "F32", [n + 1, h, w, 3], images + mean)]))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fuzz",
                                                              "corpus")
    meshes(out)
    scenes(out)
    bsdfs(out)
    coefficient_files(out)
    basis_files(out)


if __name__ == "__main__":
    main()
