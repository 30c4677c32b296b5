#!/usr/bin/python3
"""Voxelise an STL at voxel centres by ray parity along z, independently of the solver.

A voxel (i, j, k) of the grid [origin + (i, j, k) * size, ...] is inside when a ray from its
centre down to -infinity crosses the mesh an odd number of times. Crossings are found per
triangle over the voxel-centre columns its xy projection covers (the sample xy is nudged by a
tiny irrational offset so no column runs exactly through a shared edge or vertex, which would
count a crossing twice). Works for closed meshes of any orientation (OpenSCAD's output).

  stl_voxelize.py MESH.stl --grid NX NY NZ --origin OX OY OZ --size S
                  [--out VOXELS.npy] [--compare SOLVER.npy --min-agreement 0.99]

--compare loads a uint8 array of shape (NZ, NY, NX) and prints the agreement: the fraction of
voxels that agree within the bounding box of the voxels set in either grid (a stricter number
than over the whole grid), and the IoU. Exit status 1 if agreement < --min-agreement.
"""
import argparse
import struct
import sys

import numpy as np


def read_stl(path):
    """Triangles as an (n, 3, 3) float64 array; ASCII or binary STL."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) >= 84:
        n = struct.unpack("<I", data[80:84])[0]
        if 84 + 50 * n == len(data):
            rec = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
            return np.frombuffer(data, dtype=rec, count=n, offset=84)["v"].astype(np.float64)
    text = data.decode("ascii", errors="replace")
    if not text.lstrip().startswith("solid"):
        raise ValueError("%s: neither binary nor ASCII STL" % path)
    verts = [tuple(map(float, line.split()[1:4]))
             for line in text.splitlines() if line.strip().startswith("vertex")]
    if len(verts) % 3:
        raise ValueError("%s: vertex count is not a multiple of 3" % path)
    return np.array(verts, dtype=np.float64).reshape(-1, 3, 3)


def voxelize(tris, n, origin, size):
    nx, ny, nz = n
    ox, oy, oz = origin
    # toggles[j, i, k]: number of crossings whose z lies just below voxel centre k; the parity
    # of the running sum along k is inside/outside.
    toggles = np.zeros((ny, nx, nz + 1), dtype=np.int32)
    eps_x, eps_y = 1.2345678e-7 * size, 2.7182818e-7 * size
    for t in tris:
        (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = t
        area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
        if area == 0:
            continue  # parallel to the rays: never crossed
        i0 = max(int(np.ceil((min(x0, x1, x2) - ox) / size - 0.5)), 0)
        i1 = min(int(np.floor((max(x0, x1, x2) - ox) / size - 0.5)), nx - 1)
        j0 = max(int(np.ceil((min(y0, y1, y2) - oy) / size - 0.5)), 0)
        j1 = min(int(np.floor((max(y0, y1, y2) - oy) / size - 0.5)), ny - 1)
        if i0 > i1 or j0 > j1:
            continue
        xs = ox + (np.arange(i0, i1 + 1) + 0.5) * size + eps_x
        ys = oy + (np.arange(j0, j1 + 1) + 0.5) * size + eps_y
        X, Y = np.meshgrid(xs, ys)
        # Barycentric coordinates of the column in the projected triangle.
        w1 = ((X - x0) * (y2 - y0) - (x2 - x0) * (Y - y0)) / area
        w2 = ((x1 - x0) * (Y - y0) - (X - x0) * (y1 - y0)) / area
        w0 = 1 - w1 - w2
        hit = (w0 >= 0) & (w1 >= 0) & (w2 >= 0)
        if not hit.any():
            continue
        z = w0[hit] * z0 + w1[hit] * z1 + w2[hit] * z2
        kk = np.clip(np.ceil((z - oz) / size - 0.5), 0, nz).astype(np.int64)
        jj, ii = np.nonzero(hit)
        np.add.at(toggles, (jj + j0, ii + i0, kk), 1)
    inside = (np.cumsum(toggles[:, :, :nz], axis=2) % 2).astype(np.uint8)  # (ny, nx, nz)
    return np.ascontiguousarray(inside.transpose(2, 0, 1))  # (nz, ny, nx)


def compare(mine, solver):
    either = (mine > 0) | (solver > 0)
    if not either.any():
        return 1.0, 1.0
    idx = np.nonzero(either)
    box = tuple(slice(a.min(), a.max() + 1) for a in idx)
    a, b = mine[box] > 0, solver[box] > 0
    agreement = float((a == b).mean())
    iou = float((a & b).sum()) / float((a | b).sum())
    return agreement, iou


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("--grid", nargs=3, type=int, required=True, metavar=("NX", "NY", "NZ"))
    ap.add_argument("--origin", nargs=3, type=float, default=[0, 0, 0])
    ap.add_argument("--size", type=float, required=True)
    ap.add_argument("--out")
    ap.add_argument("--compare")
    ap.add_argument("--min-agreement", type=float, default=0.99)
    args = ap.parse_args()
    tris = read_stl(args.mesh)
    vox = voxelize(tris, args.grid, args.origin, args.size)
    if args.out:
        np.save(args.out, vox)
    if args.compare:
        solver = np.load(args.compare)
        if solver.shape != vox.shape:
            print("shape mismatch: %s vs %s" % (solver.shape, vox.shape))
            return 1
        agreement, iou = compare(vox, solver)
        print("agreement %.5f  IoU %.5f  voxels mesh %d solver %d  triangles %d"
              % (agreement, iou, int(vox.sum()), int((solver > 0).sum()), len(tris)))
        return 0 if agreement >= args.min_agreement else 1
    print("voxels %d of %d" % (int(vox.sum()), vox.size))
    return 0


if __name__ == "__main__":
    sys.exit(main())
