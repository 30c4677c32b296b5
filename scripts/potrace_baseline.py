"""The potrace baseline of the 2D benchmark: trace a bitmap with potrace, rasterise its SVG.

potrace's SVG paths are parsed (scad_raster.parse_svg_path: Beziers flattened), transformed and
filled at pixel centres with the SVG's own fill rule, so the trace is scored on the same grid
as the input. Used by bench_2d.py; numpy only.
"""

import os
import re
import subprocess
import xml.etree.ElementTree as ET

import numpy as np

import scad_raster  # the SVG path parser, and write_pbm for potrace's input

NUMBER_RE = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _parse_transform(text):
    """SVG transform attribute -> 3 x 3 matrix (translate, scale, matrix)."""
    m = np.eye(3)
    for name, body in re.findall(r"(\w+)\s*\(([^)]*)\)", text or ""):
        v = [float(t) for t in NUMBER_RE.findall(body)]
        t = np.eye(3)
        if name == "translate":
            t[0, 2], t[1, 2] = v[0], (v[1] if len(v) > 1 else 0.0)
        elif name == "scale":
            t[0, 0], t[1, 1] = v[0], (v[1] if len(v) > 1 else v[0])
        elif name == "matrix":
            t[:2, :] = np.array(v).reshape(3, 2).T
        else:
            raise ValueError("unsupported SVG transform %s" % name)
        m = m @ t
    return m


def rasterize_polygons(polys, width, height, fill_rule="nonzero"):
    """Fills closed polylines (pixel coordinates, y down) sampled at pixel centres.

    A centre at exactly an edge's lower end counts like a half-open interval, so shared
    vertices are not counted twice."""
    mask = np.zeros((height, width), dtype=bool)
    if not polys:
        return mask
    p0 = np.concatenate(polys)
    p1 = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
    x0, y0, x1, y1 = p0[:, 0], p0[:, 1], p1[:, 0], p1[:, 1]
    keep = y0 != y1
    x0, y0, x1, y1 = x0[keep], y0[keep], x1[keep], y1[keep]
    direction = np.where(y1 > y0, 1, -1)
    xc = np.arange(width) + 0.5
    for r in range(height):
        yc = r + 0.5
        hit = ((y0 <= yc) & (yc < y1)) | ((y1 <= yc) & (yc < y0))
        if not hit.any():
            continue
        xs = x0[hit] + (yc - y0[hit]) * (x1[hit] - x0[hit]) / (y1[hit] - y0[hit])
        left = xs[None, :] < xc[:, None]  # crossings left of each centre
        if fill_rule == "evenodd":
            mask[r] = (np.count_nonzero(left, axis=1) % 2) == 1
        else:
            mask[r] = (left.astype(np.int32) @ direction[hit]) != 0
    return mask


def _local(tag):
    return tag.rsplit("}", 1)[-1]


def rasterize_svg(svg_text, width, height):
    """Rasterises every <path> of an SVG onto a width x height pixel grid (its viewBox)."""
    root = ET.fromstring(svg_text)
    vb = [float(v) for v in NUMBER_RE.findall(root.get("viewBox", ""))]
    if len(vb) != 4:
        vb = [0.0, 0.0, float(width), float(height)]
    view = np.array([[width / vb[2], 0, -vb[0] * width / vb[2]],
                     [0, height / vb[3], -vb[1] * height / vb[3]], [0, 0, 1]])
    mask = np.zeros((height, width), dtype=bool)
    numbers = 0

    def walk(node, m, rule):
        nonlocal mask, numbers
        m = m @ _parse_transform(node.get("transform"))
        rule = node.get("fill-rule", rule)
        style = node.get("style", "")
        found = re.search(r"fill-rule\s*:\s*(\w+)", style)
        if found:
            rule = found.group(1)
        if _local(node.tag) == "path":
            d = node.get("d", "")
            numbers += len(NUMBER_RE.findall(d))
            polys = [(np.c_[p, np.ones(len(p))] @ m.T)[:, :2] for p in scad_raster.parse_svg_path(d)]
            mask |= rasterize_polygons(polys, width, height, rule)
        for child in node:
            walk(child, m, rule)

    walk(root, view, "nonzero")
    return mask, numbers


def run_potrace(mask, workdir, name):
    """Traces a foreground mask with potrace's defaults; returns (raster, numbers, svg path)."""
    h, w = mask.shape
    pbm = os.path.join(workdir, name + ".pbm")
    svg = os.path.join(workdir, name + ".potrace.svg")
    scad_raster.write_pbm(pbm, mask)
    subprocess.run(["potrace", "-b", "svg", "--flat", "-o", svg, pbm], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=60)
    with open(svg) as f:
        raster, numbers = rasterize_svg(f.read(), w, h)
    return raster, numbers, svg
