#!/usr/bin/env python3
"""Writes the hand-made seeds of the fuzz corpora (tests/fuzz/corpus/NAME/seed-*): small valid
inputs of every format and feature a target reads, so that fuzzing starts from inside the
parsers. Inputs the fuzzer found (crash-*, and any kept by hand) live beside them and are never
touched here. Run again after changing a format; the output is deterministic."""
import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def put(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, "seed-" + name), "wb") as f:
        f.write(data)


# --- OBJ (+ MTL after a "@@MTL@@" line) ---
MTL = """newmtl red
Kd 0.8 0.1 0.1
d 1.0
newmtl tex
Kd 1 1 1
map_Kd texture.png
"""
put("obj", "triangle.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
put("obj", "quad-uv-normal.obj",
    "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n")
put("obj", "negative-index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf -3 -2 -1\nf 1//1 2//-1 3//1\n")
put("obj", "materials.obj",
    "mtllib model.mtl\no cube\ng side\nusemtl red\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "v 0 0 1\nv 1 0 1\nvt 0 0\nvt 1 1\nusemtl tex\nf 1/1 2/2 3/1\ns off\nusemtl red\n"
    "f 1 4 5 6\nf 2 3 6\n\n@@MTL@@\n" + MTL)
put("obj", "crlf.obj", "v 0 0 0\r\nv 1e3 0 0\r\nv 0 1 -2.5e-1\r\nf 1 2 3\r\n")

# --- PLY ---
PLY_HEAD = "ply\nformat {fmt} 1.0\ncomment TextureFile texture.png\nelement vertex {n}\n{props}" \
           "element face {f}\nproperty list uchar int vertex_indices\n{faceprops}end_header\n"
put("ply", "ascii.ply", PLY_HEAD.format(
    fmt="ascii", n=3, f=1, faceprops="",
    props="property float x\nproperty float y\nproperty float z\n") + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
put("ply", "ascii-normals-uv.ply", PLY_HEAD.format(
    fmt="ascii", n=4, f=2, faceprops="",
    props="property double x\nproperty double y\nproperty double z\nproperty float nx\n"
          "property float ny\nproperty float nz\nproperty float s\nproperty float t\n") +
    "0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n3 0 1 2\n3 0 2 3\n")
head = PLY_HEAD.format(fmt="binary_little_endian", n=3, f=1, faceprops="",
                       props="property float x\nproperty float y\nproperty float z\n"
                             "property uchar red\nproperty uchar green\nproperty uchar blue\n")
body = b"".join(struct.pack("<3f3B", *v, 200, 100, 50) for v in [(0, 0, 0), (1, 0, 0), (0, 1, 0)])
put("ply", "binary-le-colour.ply", head.encode() + body + struct.pack("<B3i", 3, 0, 1, 2))
head = PLY_HEAD.format(fmt="binary_big_endian", n=4, f=1, faceprops="property uchar flags\n",
                       props="property double x\nproperty double y\nproperty double z\n")
body = b"".join(struct.pack(">3d", *v) for v in [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])
put("ply", "binary-be-double-quad.ply", head.encode() + body + struct.pack(">B4iB", 4, 0, 1, 2, 3, 7))

# --- OFF ---
put("off", "triangle.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
put("off", "quad-comments.off", "OFF\n# a quad\n4 1 4\n\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
put("off", "coff.off", "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n"
    "3 0 1 2 255 255 255\n")
put("off", "noff.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n")
put("off", "inline-counts.off", "OFF 4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n")

# --- STL ---
put("stl", "ascii.stl", "solid tri\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
    "vertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\n"
    "vertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid tri\n")
tris = [((0, 0, 1), (0, 0, 0), (1, 0, 0), (0, 1, 0)), ((0, 0, 1), (1, 0, 0), (1, 1, 0), (0, 1, 0))]
put("stl", "binary.stl", b"binary stl".ljust(80, b"\0") + struct.pack("<I", len(tris)) +
    b"".join(struct.pack("<12fH", *[c for v in t for c in v], 0) for t in tris))
# A binary file whose header begins with "solid" (some exporters write that).
put("stl", "binary-solid-header.stl", b"solid but binary".ljust(80, b" ") + struct.pack("<I", 1) +
    struct.pack("<12fH", *[c for v in tris[0] for c in v], 0))


# --- glTF and GLB ---
def gltf_doc(uri, extra_nodes=False, textured=False):
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    nrm = struct.pack("<9f", 0, 0, 1, 0, 0, 1, 0, 0, 1)
    uv = struct.pack("<6f", 0, 0, 1, 0, 0, 1)
    idx = struct.pack("<3H", 0, 1, 2) + b"\0\0"
    buf = pos + nrm + uv + idx
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                    "indices": 3, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.2, 1]}}],
        "buffers": [{"byteLength": len(buf)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 72, "byteLength": 24},
                        {"buffer": 0, "byteOffset": 96, "byteLength": 6}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}],
    }
    if uri is not None:
        doc["buffers"][0]["uri"] = uri
    if extra_nodes:
        doc["scenes"][0]["nodes"] = [1]
        doc["nodes"] = [{"mesh": 0, "translation": [1, 2, 3], "rotation": [0, 0, 0.7071068, 0.7071068],
                         "scale": [2, 2, 2]},
                        {"children": [0, 2], "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1]},
                        {"mesh": 0}]
    if textured:
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
        doc["textures"] = [{"source": 0}]
        doc["images"] = [{"uri": "texture.png"}]
    return doc, buf


doc, buf = gltf_doc("data:application/octet-stream;base64," + base64.b64encode(
    gltf_doc(None)[1]).decode())
put("gltf", "embedded.gltf", json.dumps(doc))
doc, buf = gltf_doc("model.bin", extra_nodes=True)
put("gltf", "external-buffer-nodes.gltf", json.dumps(doc).encode() + b"\n@@BIN@@\n" + buf)
doc, buf = gltf_doc("model.bin", textured=True)
put("gltf", "external-buffer-texture.gltf", json.dumps(doc).encode() + b"\n@@BIN@@\n" + buf)
doc, _ = gltf_doc("data:application/octet-stream;base64," + base64.b64encode(buf).decode())
del doc["meshes"][0]["primitives"][0]["indices"]
put("gltf", "no-indices.gltf", json.dumps(doc))


def glb(doc, buf):
    j = json.dumps(doc).encode()
    j += b" " * (-len(j) % 4)
    buf += b"\0" * (-len(buf) % 4)
    chunks = struct.pack("<I4s", len(j), b"JSON") + j + struct.pack("<I4s", len(buf), b"BIN\0") + buf
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


doc, buf = gltf_doc(None)
put("glb", "triangle.glb", glb(doc, buf))
doc, buf = gltf_doc(None, extra_nodes=True)
put("glb", "nodes.glb", glb(doc, buf))

# --- skeleton.bin (format in hlod/include/hlod/NodeStore.h; the target fixes the checksum) ---


def node(parent, first, count, level, payload_off, payload_size, memory, min_tri=0, splats=0):
    b = struct.pack("<5I", parent, first, count, level, 0)
    b += struct.pack("<9d", -1, -1, 0, 1, 1, 2, 0, 0, 1)  # bounds min, max, centre
    # numTri, numTexTri, minTri (0: no progression), splatCount
    b += struct.pack("<4I", 12, 0, min_tri, splats)
    b += struct.pack("<2d", 1.5, 3.0) + struct.pack("<3f", 0, 0, 1)
    b += struct.pack("<d", 0.25) + struct.pack("<2Q", payload_off, payload_size)
    b += struct.pack("<I", 0x12345678) + struct.pack("<Q", memory)
    b += struct.pack("<QQIQ", 0, 0, 0, 0)  # no texture section (offset, size, checksum, bytes)
    return b


def frame(up=2, epsg=0, to_enu=0, origin=(0.0, 0.0, 0.0), text=b""):
    b = struct.pack("<IiI", up, epsg, to_enu) + struct.pack("<3d", *origin)
    return b + struct.pack("<I", len(text)) + text


BOX = ((-1.0, -1.0, 0.0), (1.0, 1.0, 2.0))  # every seed node's box


def cell(level, x, y, first_child, child_count, first_block, block_count, box=BOX):
    return struct.pack("<7I", level, x, y, first_child, child_count, first_block, block_count) + \
        struct.pack("<6d", *box[0], *box[1])


def quadtree(domain=0, rect=(0.0, 0.0, 0.0, 0.0), depth=0, cells=(), blocks=()):
    """The block quadtree (version 6): blocks are (root, u, v)."""
    b = struct.pack("<I4dIII", domain, *rect, depth, len(cells), len(blocks))
    return b + b"".join(cells) + b"".join(struct.pack("<I2d", *blk) for blk in blocks)


def skeleton(nodes, roots, payload_bytes, name=b"meshopt", model_frame=frame(), tree=quadtree()):
    b = b"HLODSKEL" + struct.pack("<II", 6, 0x01020304)
    b += struct.pack("<dId", 3.0, 2000, 0.1) + struct.pack("<I", len(name)) + name
    b += struct.pack("<QIdQ", 24, 1, 0.5, payload_bytes) + model_frame
    b += struct.pack("<II", len(nodes), len(roots))
    b += b"".join(nodes) + b"".join(struct.pack("<I", r) for r in roots) + tree
    return b + struct.pack("<Q", 0)  # checksum: the target computes it


NO = 0xFFFFFFFF
put("skeleton", "one-node.bin", skeleton([node(NO, 0, 0, 0, 0, 100, 400)], [0], 100))
put("skeleton", "tree.bin", skeleton(
    [node(NO, 2, 2, 0, 0, 100, 400), node(NO, 0, 0, 0, 100, 50, 200),
     node(0, 0, 0, 1, 150, 60, 300, min_tri=4, splats=64), node(0, 4, 1, 1, 210, 70, 300),
     node(3, 0, 0, 2, 280, 20, 80)],
    [0, 1], 300, name=b"openmesh",
    model_frame=frame(2, 4979, 1, (51.9, 4.46, 2.0), b"EPSG:4979 (geographic): converted to east-north-up metres"),
    # Both blocks at 51.9 N 4.46 E in a geographic quadtree of depth 2: cell (2, 3) at level 2.
    tree=quadtree(1, (-180.0, -90.0, 180.0, 90.0), 2,
                  [cell(0, 0, 0, 1, 1, 0, 0), cell(1, 1, 1, 2, 1, 0, 0), cell(2, 2, 3, 0, 0, 0, 2)],
                  [(0, 4.46, 51.9), (1, 4.46, 51.9)])))
# A model without a geographic anchor: a one-cell quadtree over its own x/y.
put("skeleton", "y-up.bin", skeleton([node(NO, 0, 0, 0, 0, 100, 400)], [0], 100,
                                     model_frame=frame(up=1),
                                     tree=quadtree(2, (0.0, 0.0, 1.0, 1.0), 0,
                                                   [cell(0, 0, 0, 0, 0, 0, 1)], [(0, 0.0, 0.0)])))


# --- node payloads: the raw form, and "u32 decoded size + raw DEFLATE" as payload.bin holds it ---
def payload(vc_positions, indices, uv=False, tex=(0, 0), flags=0, version=3, progression=None,
            splats=()):
    """Format 3 (hlod/src/store/PayloadCodec.cpp); flags 1 texture coordinates, 2 one-sided,
    4 progression (moves as pairs, moveEnd, increments), 8 splats (position, radius, normal, uv)."""
    vc = len(vc_positions)
    flags |= (1 if uv else 0) | (4 if progression else 0) | (8 if splats else 0)
    b = struct.pack("<7I", 0x4C504C48, version, vc, len(indices), flags, *tex)
    b += struct.pack("<4f", 1, 0.5, 0.25, 1)
    b += b"".join(struct.pack("<3f", *p) for p in vc_positions)
    b += b"".join(struct.pack("<3f", 0, 0, 1) for _ in vc_positions)
    if uv:
        b += b"".join(struct.pack("<2f", p[0], p[1]) for p in vc_positions)
    b += b"".join(struct.pack("<I", i) for i in indices)
    if progression:
        moves, move_end, increments = progression
        b += struct.pack("<2I", len(increments), len(moves))
        b += b"".join(struct.pack("<2I", *m) for m in moves)
        b += b"".join(struct.pack("<I", e) for e in move_end)
        b += b"".join(struct.pack("<I", i) for i in increments)
    if splats:
        b += struct.pack("<I", len(splats)) + b"".join(struct.pack("<9f", *sp) for sp in splats)
    b += bytes(range(4 * tex[0] * tex[1]))
    return b


def deflated(raw):
    c = zlib.compressobj(1, zlib.DEFLATED, -15)
    return struct.pack("<I", len(raw)) + c.compress(raw) + c.flush()


tri = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
quad = tri + [(1, 1, 0)]
put("payload", "raw-triangle.bin", payload(tri, [0, 1, 2]))
put("payload", "raw-textured.bin", payload(quad, [0, 1, 2, 1, 3, 2], uv=True, tex=(2, 2), flags=2))
put("payload", "deflated-triangle.bin", deflated(payload(tri, [0, 1, 2])))
put("payload", "format2-triangle.bin", payload(tri, [0, 1, 2], version=2))
# A quad whose progression moves vertex 3 into a new vertex 4 (drops the last triangle), with two
# splats.
put("payload", "progression-splats.bin", payload(
    quad + [(0.5, 0.5, 0)], [0, 1, 2, 1, 3, 2], progression=([(3, 4)], [1], [1]),
    splats=[(0, 0, 0, 0.5, 0, 0, 1, 0, 0), (1, 1, 0, 0.5, 0, 0, 1, 1, 1)]))
put("payload", "deflated-textured.bin", deflated(payload(quad, [0, 1, 2, 1, 3, 2], uv=True, tex=(4, 2))))

# --- the view-dependent section (format in hlod/include/hlod/store/VdrStore.h): a record raw, a
# record as vdr.bin stores it (u32 raw size + raw DEFLATE), and an index ---
NONE = 0xFFFFFFFF


def vdr_record(leaves, faces, collapses, errors, stored, uv=False, tex=(0, 0), one_sided=False):
    """leaves: positions relative to the centre; faces: leaf triples (one wedge per leaf);
    collapses: (kept, removed) in order; errors: per vertex; stored: per collapse, the list of
    (face, (c0, c1, c2)) of its neighbourhood. One cluster holds everything."""
    L, I = len(leaves), len(collapses)
    V, F, W = L + I, len(faces), L
    S = sum(len(n) for n in stored)
    flags = (1 if uv else 0) | (2 if one_sided else 0) | (4 if tex[0] else 0)
    b = struct.pack("<4sII", b"HLVD", 1, flags)
    b += struct.pack("<8I", L, V, F, W, S, 1, tex[0], tex[1])
    b += struct.pack("<3d4fd", 1.0, 2.0, 3.0, 1, 1, 1, 1, min(e for e in errors if e > 0) if any(errors) else 1.0)
    for p in leaves:
        b += struct.pack("<3f", *p)
    for k, r in collapses:
        b += struct.pack("<2I", k, r)
    b += struct.pack("<%df" % V, *errors)
    b += struct.pack("<%df" % V, *([1.5] * V))
    b += struct.pack("<%dI" % V, *([0] * V))
    start = [0]
    for n in stored:
        start.append(start[-1] + len(n))
    b += struct.pack("<%dI" % (I + 1), *start)
    for n in stored:
        for face, corners in n:
            b += struct.pack("<4I", face, *corners)
    b += struct.pack("<%df" % (3 * W), *([0, 0, 1] * W))
    if uv:
        for p in leaves:
            b += struct.pack("<2f", p[0], p[1])
    b += struct.pack("<%dI" % W, *range(W))
    b += struct.pack("<%dI" % W, *([0] * W))
    for f in faces:
        b += struct.pack("<3I", *f)
    b += struct.pack("<5I2f", NONE, NONE, NONE, V, 0, 0.0, max(errors))
    b += bytes(range(4 * tex[0] * tex[1]))
    return b


def vdr_index(entries):
    b = struct.pack("<8sII", b"HLODVDRI", 1, len(entries))
    for root, offset, stored, raw in entries:
        b += struct.pack("<IQQQI", root, offset, stored, raw, 0)
        b += struct.pack("<6d", 0, 0, 0, 1, 1, 0) + struct.pack("<3I", 2, 5, 1)
    h = 1469598103934665603
    for byte in b:
        h = ((h ^ byte) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return b + struct.pack("<Q", h)


# A quad whose leaf 1 collapses into leaf 0: the triangle (0, 1, 2) goes, (0, 2, 3) stays.
quad_record = vdr_record(quad, [(0, 1, 2), (0, 2, 3)], [(0, 1)], [0, 0, 0, 0, 0.5],
                         [[(0, (0, 1, 2)), (1, (0, 2, 3))]])
put("vdr", "raw-quad.bin", quad_record)
put("vdr", "deflated-quad.bin", deflated(quad_record))
put("vdr", "raw-textured-triangle.bin", vdr_record(tri, [(0, 1, 2)], [], [0, 0, 0], [], uv=True,
                                                   tex=(2, 2), one_sided=True))
put("vdr", "index.bin", vdr_index([(0, 0, 100, 200), (3, 100, 50, 80)]))

# --- camera paths ---
key = lambda t, p, tg, **kw: dict(time=t, position=p, target=tg, **kw)
put("camera_path", "two-keys.json", json.dumps({"keyframes": [
    key(0, [0, -10, 2], [0, 0, 0]), key(5, [10, 0, 2], [0, 0, 0], up=[0, 0, 1], fov=45)]}))
put("camera_path", "bare-array.json", json.dumps([
    key(0, [0, 0, 1.7], [1, 0, 1.7]), key(1, [1, 0, 1.7], [2, 0, 1.7]),
    key(3, [1, 5, 30], [1, 6, 0], fov=70), key(4, [1, 5, 30.5], [1, 6, 0])]))
put("camera_path", "loop.json", json.dumps({"keyframes": [
    key(0, [10, 0, 5], [0, 0, 0]), key(1, [0, 10, 5], [0, 0, 0]), key(2, [-10, 0, 5], [0, 0, 0]),
    key(3, [0, -10, 5], [0, 0, 0]), key(4, [10, 0, 5], [0, 0, 0])]}))
put("camera_path", "far-from-origin.json", json.dumps({"keyframes": [
    key(86400.0, [6378137.0, 0.001, 0], [6378137.0, 10, 0], up=[1, 0, 0]),
    key(86400.016666666, [6378137.0, 0.002, 0], [6378137.0, 10, 0], up=[1, 0, 0])]}))

# --- city manifests (the target's folder holds block_0000.ply) ---
block = dict(name="block_0000", mesh="block_0000.ply", triangles=1, bounds=[[0, 0, 0], [10, 10, 5]])
put("city_manifest", "one-block.json", json.dumps(
    {"format": "hlodr-city", "version": 1, "seed": 7, "blocks": [block]}))
put("city_manifest", "anchored.json", json.dumps(
    {"format": "hlodr-city", "version": 1, "origin": {"lat": 51.9, "lon": 4.46, "height": 2},
     "blocks": [dict(block, frame="anchor", anchor={"lat": 51.9001, "lon": 4.4601}),
                dict(block, name="b2", frame="city", anchor={"lat": -89.9, "lon": 179.99})]}))
put("city_manifest", "antimeridian.json", json.dumps(
    {"format": "hlodr-city", "version": 1, "origin": {"lat": 0, "lon": 179.999},
     "blocks": [dict(block, frame="anchor", anchor={"lat": 0, "lon": -179.999}),
                dict(block, name="b3")]}))

# --- CityJSON (read as model.city.json) ---
CUBE_V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]
CUBE_SHELL = [[[0, 3, 2, 1]], [[4, 5, 6, 7]], [[0, 1, 5, 4]], [[1, 2, 6, 5]], [[2, 3, 7, 6]],
              [[3, 0, 4, 7]]]
IDENTITY = {"scale": [0.001, 0.001, 0.001], "translate": [84000.0, 446000.0, 0.0]}
put("cityjson", "solid-semantics-material.city.json", json.dumps({
    "type": "CityJSON", "version": "2.0", "transform": IDENTITY,
    "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415"},
    "appearance": {"materials": [{"name": "brick", "diffuseColor": [0.7, 0.3, 0.2],
                                  "transparency": 0.1}]},
    "vertices": [[x * 1000, y * 1000, z * 1000] for x, y, z in CUBE_V],
    "CityObjects": {"b": {"type": "Building", "geometry": [
        {"type": "Solid", "lod": "2.2", "boundaries": [CUBE_SHELL],
         "semantics": {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"},
                                    {"type": "WallSurface"}],
                       "values": [[0, 1, 2, 2, None, 2]]},
         "material": {"m": {"values": [[None, None, 0, 0, 0, 0]]}}},
        {"type": "MultiSurface", "lod": "1", "boundaries": [[[0, 1, 2, 3], [0, 2, 3]]]}]}}}))
put("cityjson", "multisolid-window-hole.city.json", json.dumps({
    "type": "CityJSON", "version": "1.1", "transform": IDENTITY,
    "vertices": [[0, 0, 0], [10000, 0, 0], [10000, 0, 6000], [0, 0, 6000],
                 [4000, 0, 2000], [4000, 0, 4000], [6000, 0, 4000], [6000, 0, 2000]] +
                [[x * 1000, y * 1000 + 5000, z * 1000] for x, y, z in CUBE_V],
    "CityObjects": {"w": {"type": "Building", "geometry": [
        {"type": "MultiSurface", "lod": 2, "boundaries": [[[0, 1, 2, 3], [4, 5, 6, 7]]]},
        {"type": "MultiSolid", "lod": 2, "boundaries": [
            [[[[i + 8 for i in ring] for ring in surface] for surface in CUBE_SHELL]]]}]}}}))
put("cityjson", "template-wgs84.city.json", json.dumps({
    "type": "CityJSON", "version": "2.0",
    "transform": {"scale": [1e-7, 1e-7, 0.001], "translate": [51.9, 4.46, 0.0]},
    "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/4979"},
    "geometry-templates": {"templates": [{"type": "MultiSurface", "lod": "1",
                                          "boundaries": [[[0, 1, 2, 3]]]}],
                           "vertices-templates": [[0, 0, 0], [1e-5, 0, 0], [1e-5, 1e-5, 0],
                                                  [0, 1e-5, 0]]},
    "vertices": [[0, 0, 0], [1000, 1000, 2000]],
    "CityObjects": {"t": {"type": "SolitaryVegetationObject", "geometry": [
        {"type": "GeometryInstance", "template": 0, "boundaries": [1],
         "transformationMatrix": [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1]},
        {"type": "MultiPoint", "lod": "1", "boundaries": [0]}]}}}))
put("cityjson", "v0-2-array-semantics.city.json", json.dumps({
    "type": "CityModel", "version": "http://www.cityjson.org/version/0.2",
    "metadata": {"crs": {"epsg": 7415}},
    "vertices": [[0.5, 0.5, 0.0], [3.5, 0.5, 0.0], [3.5, 2.5, 0.0], [2.0, 1.0, 0.0],
                 [0.5, 2.5, 0.0], [0.5, 0.5, 4.0], [3.5, 0.5, 4.0]],
    "CityObjects": {"{1}": {"type": "Building", "geometry": [
        {"type": "MultiSurface", "lod": 2, "boundaries": [[[0, 1, 2, 3, 4]], [[0, 1, 6, 5]]],
         "semantics": [{"type": "RoofSurface"}, {"type": "WallSurface"}]}]}}}))

# --- request bodies: first byte the endpoint (0 render, 1 sessions, 2 frame, 3 jobs, 4 studies) ---
cam = {"position": [0, -50, 20], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 50}
put("request_body", "render.json", b"\0" + json.dumps(
    {"scene": "city", "width": 320, "height": 240, "budgetMs": 20, "selector": "sse", "ssePx": 4,
     "camera": cam, "mode": "realtime", "format": "png", "quality": 90}).encode())
put("request_body", "render-empty.json", b"\0")
put("request_body", "session.json", b"\1" + json.dumps(
    {"scene": "city", "width": 640, "height": 480, "memoryMb": 64, "selector": "fs"}).encode())
put("request_body", "frame.json", b"\2" + json.dumps(
    {"camera": {"position": [1, 2, 3], "target": [1, 2, 0]}, "still": True, "format": "jpeg",
     "quality": 50}).encode())
put("request_body", "job-kind.json", b"\3" + json.dumps(
    {"scene": "city", "path": {"kind": "orbit", "duration": 10}, "fps": 24, "mode": "settled",
     "video": True, "frames": 100, "prefetch": True}).encode())
put("request_body", "job-keyframes.json", b"\3" + json.dumps(
    {"scene": "city", "path": {"keyframes": [key(0, [0, -10, 2], [0, 0, 0]),
                                             key(2, [5, -10, 2], [0, 0, 0], fov=40)]}}).encode())
put("request_body", "study.json", b"\4" + json.dumps(
    {"scene": "city", "path": {"kind": "walk-fly"}, "budgets": [10, 33, 100], "selectors":
     ["lakhia", "sse"], "ssePx": [2, 8], "width": 160, "height": 90, "frames": 12, "fps": 30,
     "mode": "both", "strips": 2}).encode())

# inline scenes and scene file names (the fuzz's data folder holds scene.json)
inline = {"store": "city", "camera": cam, "background": {"colour": [0.1, 0.2, 0.3]},
          "effects": {"textures": True, "shading": "blinn-phong", "sun": {"direction": [0, 0, 1]},
                      "ssao": True, "outline": {"thickness": 2}}}
put("request_body", "render-inline-scene.json", b"\0" + json.dumps(
    {"scene": inline, "width": 64, "height": 64}).encode())
put("request_body", "session-scene-file.json", b"\1" + json.dumps({"scene": "scene.json"}).encode())
put("request_body", "job-inline-scene.json", b"\3" + json.dumps(
    {"scene": {"store": "x.hlod", "effects": {"fog": {"density": 0.01}, "shadows": True}},
     "path": {"kind": "drive"}}).encode())

# --- scene files (docs/scene.md), and the repository's own scenes/ ---
put("scene_file", "doc-example.json", json.dumps({
    "store": "../out/city.hlod",
    "camera": {"position": [-300, -600, 400], "target": [400, 400, 0], "up": [0, 0, 1], "fov": 50},
    "background": {"sky": {"horizon": [0.80, 0.87, 0.95], "zenith": [0.30, 0.52, 0.86]}},
    "effects": {"textures": True, "shading": "lambert",
                "sun": {"direction": [0.45, -0.35, 0.82], "colour": [1.0, 0.96, 0.88], "intensity": 1.1},
                "fog": {"density": 0.00015}, "shadows": {"resolution": 2048},
                "ssao": {"radius": 3.0, "samples": 12}, "outline": {"colour": [0.05, 0.05, 0.05]}}}))
put("scene_file", "minimal.json", "{}")
put("scene_file", "booleans.json", json.dumps({
    "background": {"colour": [1, 1, 1]},
    "effects": {"textures": False, "shading": "blinn-phong", "sun": True, "fog": True,
                "shadows": True, "ssao": {"strength": 4}, "outline": {"threshold": 0.5, "thickness": 8}}}))
scenes = os.path.join(HERE, "..", "..", "scenes")
for name in sorted(os.listdir(scenes)) if os.path.isdir(scenes) else []:
    if name.endswith(".json"):
        with open(os.path.join(scenes, name), "rb") as f:
            put("scene_file", "scenes-" + name, f.read())

# --- 3D Tiles: tileset.json, then files of its folder after "@@FILE name@@" lines ---
def glb_triangle(offset=(0.0, 0.0, 0.0), rtc=None, double_sided=False):
    """A binary glTF of one triangle (y up), with normals, in the 2.0 layout."""
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 0, -1)
    nrm = struct.pack("<9f", 0, 1, 0, 0, 1, 0, 0, 1, 0)
    idx = struct.pack("<3H", 0, 1, 2) + b"\0\0"
    binary = pos + nrm + idx
    gltf = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "translation": list(offset)}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                        "material": 0}]}],
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.6, 0.7, 1]},
                           "doubleSided": double_sided}],
            "buffers": [{"byteLength": len(binary)}],
            "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                            {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                            {"buffer": 0, "byteOffset": 72, "byteLength": 6}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0, 0, -1], "max": [1, 0, 0]},
                          {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
                          {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}]}
    if rtc:
        gltf["extensionsUsed"] = ["CESIUM_RTC"]
        gltf["extensions"] = {"CESIUM_RTC": {"center": list(rtc)}}
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(binary)
    return (struct.pack("<4sII", b"glTF", 2, total) + struct.pack("<I4s", len(text), b"JSON") + text
            + struct.pack("<I4s", len(binary), b"BIN\0") + binary)


def b3dm_of(glb, feature_table, batch_table=None):
    ft = json.dumps(feature_table).encode()
    ft += b" " * (-(28 + len(ft)) % 8)
    bt = json.dumps(batch_table).encode() if batch_table else b""
    bt += b" " * (-len(bt) % 8)
    return struct.pack("<4s6I", b"b3dm", 1, 28 + len(ft) + len(bt) + len(glb), len(ft), 0,
                       len(bt), 0) + ft + bt + glb


def tile(uri, error, children=None, **extra):
    t = {"boundingVolume": {"box": [0, 0, 0, 10, 0, 0, 0, 10, 0, 0, 0, 10]}, "geometricError": error}
    if uri:
        t["content"] = {"uri": uri}
    if children:
        t["children"] = children
    t.update(extra)
    return t


def tileset_of(root, version="1.1", **extra):
    root.setdefault("refine", "REPLACE")
    t = {"asset": {"version": version}, "geometricError": 100, "root": root}
    t.update(extra)
    return json.dumps(t).encode()


def files(main, **others):
    out = main
    for name, data in others.items():
        out += b"\n@@FILE " + name.encode() + b"@@\n" + (data if isinstance(data, bytes) else data.encode())
    return out


put("tileset", "glb-tree.txt", files(
    tileset_of(tile("a.glb", 4, [tile("b.glb", 0), tile("c.glb", 0)])),
    **{"a.glb": glb_triangle(), "b.glb": glb_triangle((1, 0, 0)), "c.glb": glb_triangle((0, 0, 1))}))
put("tileset", "b3dm-rtc-batch.txt", files(
    tileset_of(tile("a.b3dm", 2, [tile("b.b3dm", 0)]), "1.0", extras={"gltfUpAxis": "Y"}),
    **{"a.b3dm": b3dm_of(glb_triangle(), {"BATCH_LENGTH": 1, "RTC_CENTER": [10, 20, 30]},
                         {"name": ["one"]}),
       "b.b3dm": b3dm_of(glb_triangle(rtc=(1, 2, 3), double_sided=True), {"BATCH_LENGTH": 0})}))
put("tileset", "external-and-add.txt", files(
    tileset_of(tile("a.glb", 4, [tile("inner.json", 2)], refine="ADD",
                    transform=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 5, 5, 1])),
    **{"a.glb": glb_triangle(), "inner.json": tileset_of(tile("b.glb", 0)).decode(),
       "b.glb": glb_triangle((2, 0, 0))}))
put("tileset", "empty-root-contents.txt", files(
    tileset_of(tile("", 8, [tile("", 4, [tile("a.glb", 0)]),
                            {"boundingVolume": {"sphere": [0, 0, 0, 5]}, "geometricError": 0,
                             "contents": [{"uri": "a.glb"}, {"uri": "b.glb"}]}])),
    **{"a.glb": glb_triangle(), "b.glb": glb_triangle((0, 1, 0))}))
# An earth-centred tileset: a region volume and ECEF-sized RTC.
put("tileset", "region-ecef.txt", files(
    tileset_of({"boundingVolume": {"region": [0.14, 0.82, 0.15, 0.83, 0, 100]}, "geometricError": 0,
                "content": {"uri": "a.b3dm"}}),
    **{"a.b3dm": b3dm_of(glb_triangle(), {"BATCH_LENGTH": 0,
                                          "RTC_CENTER": [4302984.0, 636924.0, 4643160.0]})}))
# Implicit quadtree: a binary subtree (root and children 0 and 3), then a child subtree.
sub_json = json.dumps({"buffers": [{"byteLength": 8}],
                       "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 1},
                                       {"buffer": 0, "byteOffset": 1, "byteLength": 2}],
                       "tileAvailability": {"bitstream": 0},
                       "contentAvailability": [{"bitstream": 0}],
                       "childSubtreeAvailability": {"bitstream": 1}}).encode()
sub_json += b" " * (-len(sub_json) % 8)
sub_bin = bytes([0b10011, 1, 0, 0, 0, 0, 0, 0])  # child subtree 0: below tile 1/0/0
subtree = struct.pack("<4sIQQ", b"subt", 1, len(sub_json), len(sub_bin)) + sub_json + sub_bin
leaf = json.dumps({"tileAvailability": {"constant": 1}, "contentAvailability": [{"constant": 1}],
                   "childSubtreeAvailability": {"constant": 0}})
put("tileset", "implicit-quadtree.txt", files(
    tileset_of(tile("c-{level}-{x}-{y}.glb", 16,
                    implicitTiling={"subdivisionScheme": "QUADTREE", "subtreeLevels": 2,
                                    "availableLevels": 4, "subtrees": {"uri": "s-{level}-{x}-{y}.subtree"}})),
    **{"s-0-0-0.subtree": subtree, "s-2-0-0.subtree": leaf, "c-0-0-0.glb": glb_triangle(),
       "c-1-0-0.glb": glb_triangle(), "c-1-1-1.glb": glb_triangle(), "c-2-0-0.glb": glb_triangle(),
       "c-3-0-0.glb": glb_triangle(), "c-3-1-0.glb": glb_triangle(), "c-3-0-1.glb": glb_triangle(),
       "c-3-1-1.glb": glb_triangle()}))


# --- switch_message: the occlusion-switch's messages (hlod/runtime/VisibleSetDelta.h) ---
def switch_message(frame, added, removed, camera=(0.0, 0.0, 10.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)):
    body = struct.pack("<9d", *camera) + struct.pack("<%dI" % (len(added) + len(removed)),
                                                     *(list(added) + list(removed)))
    return struct.pack("<5I", 0x534F4C48, frame, len(added), len(removed), len(body)) + body
put("switch_message", "first-frame.bin", switch_message(0, range(0, 40, 3), []))
put("switch_message", "delta.bin", switch_message(7, [5, 9], [1, 2, 60000]))
put("switch_message", "empty.bin", switch_message(3, [], []))
