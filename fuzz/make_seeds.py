#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets: a few small valid files per target, in
fuzz/corpus/TARGET/seed-*. Pure Python (struct, zlib), so that the seeds are reproducible on
any machine; the regression inputs (regress-*) found by fuzzing are kept beside them and are
not touched.

    python3 fuzz/make_seeds.py
"""
import json
import os
import struct
import zlib

CORPUS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def put(target, name, data):
    folder = os.path.join(CORPUS, target)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, "seed-" + name), "wb") as f:
        f.write(data)


def disc(w, h):
    """A filled disc on a w x h canvas: True inside."""
    return [[(x - w / 2 + 0.5) ** 2 + (y - h / 2 + 0.5) ** 2 < (min(w, h) / 3) ** 2
             for x in range(w)] for y in range(h)]


# --- images -------------------------------------------------------------------------------

ADAM7 = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]


def png(w, h, bit_depth, colour, rows, palette=None, trns=None, interlace=0):
    """rows: the scanlines (bytes, whole bytes per pixel when interlaced)."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    if interlace:
        bpp = len(rows[0]) // w
        raw = b""
        for x0, y0, dx, dy in ADAM7:
            for y in range(y0, h, dy):
                line = b"".join(rows[y][x * bpp:(x + 1) * bpp] for x in range(x0, w, dx))
                if line:
                    raw += b"\0" + line
    else:
        raw = b"".join(b"\0" + r for r in rows)
    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bit_depth, colour, 0, 0, interlace))
    if palette:
        out += chunk(b"PLTE", palette)
    if trns:
        out += chunk(b"tRNS", trns)
    return out + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def images():
    w, h = 12, 9
    m = disc(w, h)
    grey8 = [bytes(0 if v else 255 for v in row) for row in m]
    put("png", "grey8.png", png(w, h, 8, 0, grey8))
    put("png", "grey16.png", png(w, h, 16, 0, [b"".join(struct.pack(">H", 0 if v else 65535) for v in row) for row in m]))
    put("png", "rgba.png", png(w, h, 8, 6, [b"".join(bytes((0, 0, 0, 255)) if v else bytes((255, 255, 255, 0)) for v in row) for row in m]))
    put("png", "palette.png", png(w, h, 8, 3, [bytes(1 if v else 0 for v in row) for row in m],
                                  palette=b"\xff\xff\xff\x00\x00\x00", trns=b"\x00\xff"))
    put("png", "grey1.png", png(8, 4, 1, 0, [b"\x0f", b"\xf0", b"\x3c", b"\xc3"]))
    put("png", "interlaced.png", png(w, h, 8, 2, [b"".join(bytes((0, 0, 0)) if v else bytes((255, 255, 255)) for v in row) for row in m], interlace=1))

    def bmp(bits, rows_bottom_up, palette=b"", height_sign=1):
        stride = (len(rows_bottom_up[0]) + 3) & ~3
        body = b"".join(r + b"\0" * (stride - len(r)) for r in rows_bottom_up)
        off = 14 + 40 + len(palette)
        info = struct.pack("<IiiHHIIiiII", 40, w, height_sign * h, 1, bits, 0, len(body), 2835, 2835,
                           len(palette) // 4, 0)
        return b"BM" + struct.pack("<IHHI", off + len(body), 0, 0, off) + info + palette + body
    up = list(reversed(m))
    put("bmp", "rgb24.bmp", bmp(24, [b"".join(b"\0\0\0" if v else b"\xff\xff\xff" for v in r) for r in up]))
    put("bmp", "pal8.bmp", bmp(8, [bytes(0 if v else 1 for v in r) for r in up], palette=b"\0\0\0\0\xff\xff\xff\0"))
    put("bmp", "rgba32.bmp", bmp(32, [b"".join(b"\0\0\0\xff" if v else b"\xff\xff\xff\0" for v in r) for r in up]))
    put("bmp", "topdown.bmp", bmp(24, [b"".join(b"\0\0\0" if v else b"\xff\xff\xff" for v in r) for r in m], height_sign=-1))

    def tga(kind, bits, pixels, cmap=b"", descriptor=0x20):
        head = struct.pack("<BBBHHBHHHHBB", 0, 1 if cmap else 0, kind, 0, len(cmap) // 3 if cmap else 0,
                           24 if cmap else 0, 0, 0, w, h, bits, descriptor)
        return head + cmap + pixels
    flat = [v for row in m for v in row]
    put("tga", "grey.tga", tga(3, 8, bytes(0 if v else 255 for v in flat)))
    put("tga", "rgb.tga", tga(2, 24, b"".join(b"\0\0\0" if v else b"\xff\xff\xff" for v in flat)))
    put("tga", "cmap.tga", tga(1, 8, bytes(0 if v else 1 for v in flat), cmap=b"\0\0\0\xff\xff\xff"))
    # Run-length: each row as one run-length packet of its first pixel and raw packets after.
    rle = b""
    for row in m:
        rle += bytes((0x80 | 0,)) + (b"\0" if row[0] else b"\xff")
        rle += bytes((len(row) - 2,)) + bytes(0 if v else 255 for v in row[1:])
    put("tga", "rle.tga", tga(11, 8, rle))

    pbm_rows = ["".join("1" if v else "0" for v in row) for row in m]
    put("netpbm", "p1.pbm", "P1\n# disc\n%d %d\n%s\n" % (w, h, "\n".join(" ".join(r) for r in pbm_rows)))
    put("netpbm", "p2.pgm", "P2\n%d %d\n15\n%s\n" % (w, h, "\n".join(" ".join("0" if v else "15" for v in row) for row in m)))
    put("netpbm", "p3.ppm", "P3\n%d %d 255\n%s\n" % (w, h, "\n".join(" ".join("0 0 0" if v else "255 255 255" for v in row) for row in m)))
    p4 = b"".join(bytes(int("".join("1" if v else "0" for v in row + [False] * 4)[i:i + 8], 2)
                        for i in range(0, 16, 8)) for row in m)
    put("netpbm", "p4.pbm", b"P4\n%d %d\n" % (w, h) + p4)
    put("netpbm", "p5.pgm", b"P5 %d %d 255\n" % (w, h) + b"".join(grey8))
    put("netpbm", "p5_16.pgm", b"P5\n%d %d\n65535\n" % (w, h) + b"".join(b"".join(struct.pack(">H", 0 if v else 65535) for v in row) for row in m))
    put("netpbm", "p6.ppm", b"P6\n%d %d\n255\n" % (w, h) + b"".join(b"".join(b"\0\0\0" if v else b"\xff\xff\xff" for v in row) for row in m))


def jpeg_seeds():
    # A baseline 8 x 8 grey JPEG (one DC-only block) and a 16 x 8 one, written by hand: DQT all
    # ones, the standard luminance DC/AC Huffman tables.
    dc_bits = bytes([0, 1, 5, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0])
    dc_vals = bytes(range(12))
    ac_bits = bytes([0, 2, 1, 3, 3, 2, 4, 3, 5, 5, 4, 4, 0, 0, 1, 0x7d])
    ac_vals = bytes.fromhex(
        "01020300041105122131410613516107227114328191a1082342b1c11552d1f02433627282090a161718191a25262728292a3435363738393a434445464748494a535455565758595a636465666768696a737475767778797a838485868788898a92939495969798999aa2a3a4a5a6a7a8a9aab2b3b4b5b6b7b8b9bac2c3c4c5c6c7c8c9cad2d3d4d5d6d7d8d9dae1e2e3e4e5e6e7e8e9eaf1f2f3f4f5f6f7f8f9fa")

    def seg(marker, body):
        return bytes((0xFF, marker)) + struct.pack(">H", len(body) + 2) + body

    def jpeg(w, h, scan):
        out = b"\xff\xd8"
        out += seg(0xE0, b"JFIF\0\x01\x01\0\0\x01\0\x01\0\0")
        out += seg(0xDB, b"\0" + bytes([1] * 64))
        out += seg(0xC0, struct.pack(">BHHB", 8, h, w, 1) + b"\x01\x11\x00")
        out += seg(0xC4, b"\x00" + dc_bits + dc_vals + b"\x10" + ac_bits + ac_vals)
        out += seg(0xDA, b"\x01\x01\x00\x00\x3f\x00")
        return out + scan + b"\xff\xd9"
    # DC category 0 (code 00) then EOB (1010): 001010 padded with ones.
    put("jpeg", "grey8.jpg", jpeg(8, 8, bytes([0b00101011])))
    put("jpeg", "grey16.jpg", jpeg(16, 8, bytes([0b00101000, 0b10101111])))


# --- meshes ---------------------------------------------------------------------------------

TETRA_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TETRA_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def meshes():
    facets = "".join(
        "facet normal 0 0 0\n outer loop\n" + "".join("  vertex %g %g %g\n" % TETRA_V[i] for i in f) +
        " endloop\nendfacet\n" for f in TETRA_F)
    put("stl", "ascii.stl", "solid tetra\n" + facets + "endsolid tetra\n")
    put("stl", "two_solids.stl", "solid a\n" + facets + "endsolid a\nsolid b\n" + facets + "endsolid b\n")
    binary = b"csgfit binary tetra".ljust(80, b" ") + struct.pack("<I", len(TETRA_F))
    for f in TETRA_F:
        binary += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *TETRA_V[i]) for i in f) + b"\0\0"
    put("stl", "binary.stl", binary)
    put("stl", "binary_solid_header.stl", b"solid but binary".ljust(80, b" ") + binary[80:])

    verts = "".join("v %g %g %g\n" % v for v in TETRA_V)
    put("obj", "tetra.obj", "# tetra\no t\n" + verts + "".join("f %d %d %d\n" % tuple(i + 1 for i in f) for f in TETRA_F))
    put("obj", "slashes.obj", verts + "vt 0 0\nvn 0 0 1\n" +
        "".join("f %d/1/1 %d//1 %d\n" % tuple(i + 1 for i in f) for f in TETRA_F))
    put("obj", "negative_quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nf -5 -2 -3 -4\n"
        "f 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n")

    put("off", "tetra.off", "OFF\n4 4 6\n" + "".join("%g %g %g\n" % v for v in TETRA_V) +
        "".join("3 %d %d %d\n" % f for f in TETRA_F))
    put("off", "coff_comments.off", "COFF\n# colours\n4 4 0\n" + "".join("%g %g %g 255 0 0 255\n" % v for v in TETRA_V) +
        "".join("3 %d %d %d 0 0 255\n" % f for f in TETRA_F))
    put("off", "pyramid_quad.off", "OFF\n5 5 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n4 0 3 2 1\n3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n")

    def ply_header(fmt, extra_vertex="", face="property list uchar int vertex_indices", comments=""):
        return ("ply\nformat %s 1.0\n%selement vertex 4\nproperty float x\nproperty float y\nproperty float z\n%s"
                "element face 4\n%s\nend_header\n" % (fmt, comments, extra_vertex, face))
    put("ply", "ascii.ply", ply_header("ascii") + "".join("%g %g %g\n" % v for v in TETRA_V) +
        "".join("3 %d %d %d\n" % f for f in TETRA_F))
    for fmt, e in (("binary_little_endian", "<"), ("binary_big_endian", ">")):
        body = b"".join(struct.pack(e + "3f", *v) for v in TETRA_V)
        body += b"".join(struct.pack(e + "B3i", 3, *f) for f in TETRA_F)
        put("ply", fmt + ".ply", ply_header(fmt).encode() + body)
    body = b"".join(struct.pack("<3fB", *v, 7) for v in TETRA_V)
    body += b"".join(struct.pack("<H3I", 3, *f) for f in TETRA_F)
    put("ply", "extra_props.ply", ply_header("binary_little_endian", "property uchar red\n",
                                            "property list ushort uint vertex_index",
                                            "comment made by make_seeds.py\nobj_info tetra\n").encode() + body)


# --- voxels ---------------------------------------------------------------------------------

def npy(descr, shape, data, fortran=False, version=1):
    head = "{'descr': '%s', 'fortran_order': %s, 'shape': (%s), }" % (
        descr, "True" if fortran else "False", ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else ""))
    size_field = 2 if version == 1 else 4
    pad = (-(6 + 2 + size_field + len(head) + 1)) % 64
    head = head + " " * pad + "\n"
    return (b"\x93NUMPY" + bytes((version, 0)) +
            struct.pack("<H" if version == 1 else "<I", len(head)) + head.encode() + data)


def voxels():
    n = 4
    solid = [1 if 0 < i < 3 and 0 < j < 3 and k < 3 else 0 for i in range(n) for j in range(n) for k in range(n)]
    put("npy_voxels", "bool.npy", npy("|b1", (n, n, n), bytes(solid)))
    put("npy_voxels", "uint8_fortran.npy", npy("|u1", (n, n, n), bytes(solid), fortran=True))
    put("npy_voxels", "float32.npy", npy("<f4", (n, n, n), b"".join(struct.pack("<f", v) for v in solid)))
    put("npy_voxels", "int64_be_v2.npy", npy(">i8", (2, 2, 2), b"".join(struct.pack(">q", v) for v in solid[:8]), version=2))
    runs = []
    for v in solid:
        if runs and runs[-1][0] == v and runs[-1][1] < 255:
            runs[-1][1] += 1
        else:
            runs.append([v, 1])
    rle = b"".join(bytes(r) for r in runs)
    put("binvox", "cube.binvox", b"#binvox 1\ndim 4 4 4\ntranslate 0 0 0\nscale 1\ndata\n" + rle)
    put("binvox", "translated.binvox", b"#binvox 1\ndim 4 4 4\ntranslate -1.5 2 0.25\nscale 3.5\ndata\n" + rle)
    put("binvox", "flat.binvox", b"#binvox 1\ndim 2 3 1\ndata\n\x01\x02\x00\x04")


# --- JSON -----------------------------------------------------------------------------------

def leaves_of(node):
    """The leaves of a JSON tree in pre-order."""
    if "children" not in node:
        return [node]
    return [leaf for child in node["children"] for leaf in leaves_of(child)]


def documents():
    canvas = {"width_px": 96, "height_px": 80, "pixel_size": 0.5, "thickness": 0.0}
    tree = {"op": "difference", "children": [
        {"type": "rectangle", "cx": 24, "cy": 20, "w": 40, "h": 30, "angle": 0},
        {"op": "union", "children": [
            {"type": "circle", "cx": 12, "cy": 20, "r": 5},
            {"type": "ellipse", "cx": 30, "cy": 22, "rx": 6, "ry": 3, "angle": 30},
            {"type": "triangle", "cx": 36, "cy": 10, "w": 6, "h": 4, "angle": 90, "apex": 0.5}]},
        {"op": "intersection", "children": [
            {"type": "circle", "cx": 24, "cy": 30, "r": 4},
            {"type": "rectangle", "cx": 24, "cy": 30, "w": 6, "h": 6}]}]}
    stats = {"k": 25, "score": 120.5, "iou": 0.99, "primitives": 6}
    put("json2d", "document.json", json.dumps({
        "schema": "csgfit/1", "dimension": 2, "units": "mm", "canvas": canvas, "source": "x.png",
        "tree": tree, "stats": stats, "alternatives": [{"tree": tree["children"][0], "stats": stats}]}, indent=1))
    put("json2d", "bare_node.json", json.dumps({"op": "union", "children": [
        {"type": "rect", "cx": 10, "cy": 10, "w": 4, "h": 4},
        {"type": "triangle", "points": [[0, 0], [10, 0], [3, 8]]}]}))
    tree_b = json.loads(json.dumps(tree))
    put("json2d", "morph.json", json.dumps({
        "schema": "csgfit/1", "dimension": 2, "units": "mm", "canvas": canvas, "source": "a.png",
        "tree": tree, "stats": stats,
        "morph": {"source_b": "b.png", "tree_b": tree_b, "stats_b": stats, "rotate": "cw",
                  "leaves": [{"in_a": True, "in_b": True}] * len(leaves_of(tree))}}, indent=1))
    put("json2d", "tiny.json", '{"schema":"csgfit/1","canvas":{"width_px":8,"height_px":8,"pixel_size":1},'
        '"tree":{"type":"square","cx":4,"cy":4,"w":2,"h":2}}')

    def p(kind, **fields):
        node = {"type": kind, "center": [0.5, -1, 2]}
        node.update(fields)
        return node
    tree3 = {"op": "difference", "children": [
        p("box", size=[4, 3, 2], rotation=[1, 0, 0, 0]),
        {"op": "union", "children": [
            p("sphere", r=1), p("cylinder", r=0.5, h=3, euler_deg=[90, 0, 0]),
            p("cone", r1=1, r2=0.25, h=2, rotation=[0.7071068, 0.7071068, 0, 0]),
            p("ellipsoid", radii=[1, 0.5, 0.25]), p("torus", R=1, r=0.2),
            p("prism", w=1, h=1, depth=2, apex=0.25)]},
        {"op": "intersection", "children": [p("sphere", r=2), p("box", size=[1, 1, 1])]}]}
    put("json3d", "document.json", json.dumps({
        "schema": "csgfit/1", "dimension": 3, "units": "mm", "source": "part.stl",
        "grid": {"nx": 8, "ny": 8, "nz": 8, "origin": [0, 0, 0], "voxel_size": 0.5},
        "frame": [1, 0, 0, 0], "tree": tree3, "stats": {"k": 10, "iou": 0.98}}, indent=1))
    put("json3d", "sphere.json", '{"schema":"csgfit/1","dimension":3,"units":"mm","tree":'
        '{"type":"sphere","center":[0,0,0],"r":1}}')

    put("range_sidecar", "ortho.json", json.dumps({
        "projection": "orthographic", "pixel_size": 0.05, "width": 64, "height": 48,
        "cx": 32, "cy": 24, "depth_unit": 0.001, "no_return": 0,
        "camera_to_world": [[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, 10], [0, 0, 0, 1]]}))
    put("range_sidecar", "pinhole.json", json.dumps({
        "projection": "pinhole", "fx": 80, "fy": 80, "depth_unit": 0.0001,
        "camera_to_world": [[0, 0, 1, -5], [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 1]]}))
    put("range_sidecar", "minimal.json", '{"projection": "orthographic", "pixel_size": 1}')


# --- OpenSCAD CSG programs ------------------------------------------------------------------

def openscad_programs():
    # OpenSCAD 2021 output (openscad -o x.csg) for every construct, a benchmark solution, and syntax.
    put("openscad_csg", 'every_construct.csg', 'union() {\n\tcube(size = [1, 2, 3], center = true);\n\tsphere($fn = 8, $fa = 12, $fs = 2, r = 2);\n}\ndifference() {\n\tcylinder($fn = 0, $fa = 12, $fs = 2, h = 3, r1 = 1, r2 = 0.5, center = true);\n\tmultmatrix([[1, 0, 0, 1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {\n\t\tmultmatrix([[0.866025, -0.5, 0, 0], [0.5, 0.866025, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {\n\t\t\tmultmatrix([[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {\n\t\t\t\tmultmatrix([[-1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {\n\t\t\t\t\tcube(size = [1, 1, 1], center = false);\n\t\t\t\t}\n\t\t\t}\n\t\t}\n\t}\n}\nintersection() {\n\tsphere($fn = 0, $fa = 12, $fs = 2, r = 1);\n\tcube(size = [1, 1, 1], center = false);\n}\ncolor([1, 0, 0, 0.5]) {\n\tcube(size = [1, 1, 1], center = false);\n}\ncolor([0.1, 0.2, 0.3, 1]) {\n\tcube(size = [1, 1, 1], center = false);\n}\nrender(convexity = 2) {\n\tcube(size = [1, 1, 1], center = false);\n}\nlinear_extrude(height = 2, center = true, convexity = 1, twist = 30, slices = 4, scale = [0.5, 0.5]) {\n\tcircle($fn = 0, $fa = 12, $fs = 2, r = 1);\n}\nrotate_extrude(angle = 90, convexity = 2, $fn = 0, $fa = 12, $fs = 2) {\n\tmultmatrix([[1, 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {\n\t\tsquare(size = [1, 2], center = true);\n\t}\n}\nlinear_extrude(height = 1, center = false, convexity = 1, scale = [1, 1], $fn = 0, $fa = 12, $fs = 2) {\n\tpolygon(points = [[0, 0], [1, 0], [0, 1]], paths = [[0, 1, 2]], convexity = 1);\n}\nhull() {\n\tcube(size = [1, 1, 1], center = false);\n\tmultmatrix([[1, 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {\n\t\tsphere($fn = 0, $fa = 12, $fs = 2, r = 1);\n\t}\n}\nminkowski(convexity = 0) {\n\tcube(size = [1, 1, 1], center = false);\n\tsphere($fn = 0, $fa = 12, $fs = 2, r = 0.1);\n}\npolyhedron(points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], faces = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]], convexity = 1);\nlinear_extrude(height = 1, center = false, convexity = 1, scale = [1, 1], $fn = 0, $fa = 12, $fs = 2) {\n\ttext(text = "a"b\\c\td", size = 3, spacing = 1, font = "", direction = "ltr", language = "en", script = "Latn", halign = "left", valign = "baseline", $fn = 0, $fa = 12, $fs = 2);\n}\nlinear_extrude(height = 1, center = false, convexity = 1, scale = [1, 1], $fn = 0, $fa = 12, $fs = 2) {\n\toffset(r = 0.5, $fn = 0, $fa = 12, $fs = 2) {\n\t\tsquare(size = [1, 1], center = false);\n\t}\n}\nprojection(cut = true, convexity = 0) {\n\tcube(size = [1, 1, 1], center = false);\n}\nsurface(file = "x.dat", center = false, invert = false, timestamp = 0);\nimport(file = "x.stl", layer = "", origin = [0, 0], scale = 1, convexity = 1, $fn = 0, $fa = 12, $fs = 2, timestamp = 0);\ngroup() {\n\tcube(size = [1e-05, 1e-05, 1e-05], center = false);\n}\ncube(size = [-0, -0, -0], center = false);\n\n')
    put("openscad_csg", 'inversecsg_011.csg', 'intersection() {\n\tmultmatrix([[1, 0, 0, -0.504], [0, 1, 0, -0.504], [0, 0, 1, -6], [0, 0, 0, 1]]) {\n\t\tcube(size = [1.008, 1.009, 12], center = false);\n\t}\n\tunion() {\n\t\tdifference() {\n\t\t\tmultmatrix([[1, 0, 0, -0.002], [0, 1, 0, 0.001], [0, 0, 1, 4.488], [0, 0, 0, 1]]) {\n\t\t\t\tcylinder($fn = 12, $fa = 12, $fs = 2, h = 0.512, r1 = 0.42, r2 = 0.42, center = false);\n\t\t\t}\n\t\t\tmultmatrix([[1, 0, 0, -0.001], [0, 1, 0, 0], [0, 0, 1, -18.1], [0, 0, 0, 1]]) {\n\t\t\t\tcylinder($fn = 12, $fa = 12, $fs = 2, h = 36.2, r1 = 0.261, r2 = 0.261, center = false);\n\t\t\t}\n\t\t}\n\t\tmultmatrix([[1, 0, 0, -0.001], [0, 1, 0, 0], [0, 0, 1, -5], [0, 0, 0, 1]]) {\n\t\t\tcylinder($fn = 12, $fa = 12, $fs = 2, h = 9.756, r1 = 0.261, r2 = 0.261, center = false);\n\t\t}\n\t}\n}\n\n')
    put("openscad_csg", 'syntax.csg', 'multmatrix([[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]) cube(size = [1e-05, -0, 2]);\n// c\n/* b */ group() { ; }\ntext(text = "a\\"b\\\\c", size = 3);\n')

    put("openscad_csg", "lock.csg", """multmatrix([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {
\tdifference() {
\t\tintersection() {
\t\t\tcube(size = [10, 10, 10], center = true);
\t\t\tsphere($fn = 60, $fa = 12, $fs = 2, r = 6.25);
\t\t}
\t\tunion() {
\t\t\tmultmatrix([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]]) {
\t\t\t\tcylinder($fn = 60, $fa = 12, $fs = 2, h = 15, r1 = 2.5, r2 = 2.5, center = true);
\t\t\t}
\t\t\tcylinder($fn = 60, $fa = 12, $fs = 2, h = 15, r1 = 2.5, r2 = 2.5, center = true);
\t\t}
\t}
}
""")
    put("openscad_csg", "extrusions.csg", """group() {
\tlinear_extrude(height = 10, center = false, convexity = 1, twist = 30, slices = 5, scale = [1, 0.5]) {
\t\tdifference() { square(size = [4, 2], center = true); circle($fn = 0, $fa = 12, $fs = 2, r = 0.5); }
\t}
\trotate_extrude(angle = 270, convexity = 2, $fn = 0, $fa = 12, $fs = 2) {
\t\tpolygon(points = [[1, 0], [2, 0], [2, 1]], paths = [[0, 1, 2]], convexity = 1);
\t}
\tcolor([1, 0, 0, 1]) render(convexity = 2) hull() { cube(size = 1); sphere(r = 1); }
\ttext(text = "a\\"b", size = 10, font = "", halign = "left", valign = "baseline", spacing = 1);
}
""")


# --- range inputs ---------------------------------------------------------------------------

def ranges():
    w, h = 10, 8
    m = disc(w, h)
    put("depth_png", "depth16.png", png(w, h, 16, 0, [b"".join(struct.pack(">H", 1000 + 10 * x if v else 0)
                                                               for x, v in enumerate(row)) for row in m]))
    put("depth_png", "depth16_interlaced.png", png(w, h, 16, 0, [b"".join(struct.pack(">H", 500 if v else 0) for v in row)
                                                                 for row in m], interlace=1))
    depth = [(1.0 + 0.1 * x if v else float("nan")) for row in m for x, v in enumerate(row)]
    put("npy_range", "depth_f4.npy", npy("<f4", (h, w), b"".join(struct.pack("<f", d) for d in depth)))
    put("npy_range", "depth_f8.npy", npy("<f8", (h, w), b"".join(struct.pack("<d", d) for d in depth)))
    cloud = b"".join(struct.pack("<3f", x * 0.1, y * 0.1, 1.0 if m[y][x] else float("nan"))
                     for y in range(h) for x in range(w))
    put("npy_range", "cloud_f4.npy", npy("<f4", (h, w, 3), cloud))

    pts = [(x * 0.1, y * 0.1, 0.05 * (x + y)) for y in range(4) for x in range(5)]
    put("xyz", "points.xyz", "# points\n" + "".join("%g %g %g\n" % p for p in pts))
    put("xyz", "normals.xyz", "".join("%g %g %g 0 0 1\n" % p for p in pts))
    put("xyz", "commas_tabs.xyz", "".join("%g\t%g\t%g\r\n" % p for p in pts))
    head = "ply\nformat %s 1.0\nobj_info width 5\nobj_info height 4\nelement vertex 20\n" \
           "property float x\nproperty float y\nproperty float z\n%send_header\n"
    put("ply_points", "organised_ascii.ply", head % ("ascii", "") + "".join("%g %g %g\n" % p for p in pts))
    put("ply_points", "normals_le.ply", (head % ("binary_little_endian", "property float nx\nproperty float ny\nproperty float nz\n")).encode()
        + b"".join(struct.pack("<6f", *p, 0, 0, 1) for p in pts))
    put("ply_points", "unorganised_be.ply", b"ply\nformat binary_big_endian 1.0\nelement vertex 20\nproperty double x\n"
        b"property double y\nproperty double z\nend_header\n" + b"".join(struct.pack(">3d", *p) for p in pts))


if __name__ == "__main__":
    images()
    jpeg_seeds()
    meshes()
    voxels()
    documents()
    ranges()
    openscad_programs()
