"""Mesh inputs of "Mesh to CSG": FreeCAD meshes as numpy arrays and the file types the fit
reads. Needs FreeCAD (headless is fine), not its GUI."""

import os

#: Files csgfit.fit_mesh reads: meshes, then voxel grids.
MESH_EXTENSIONS = (".stl", ".obj", ".off", ".ply")
VOXEL_EXTENSIONS = (".npy", ".binvox")
FILE_FILTER = ("Meshes and voxel grids (*.stl *.obj *.off *.ply *.npy *.binvox);;"
               "All files (*)")


def is_fit_input(path):
    """Whether the extension is one the 3D fit reads."""
    return os.path.splitext(path)[1].lower() in MESH_EXTENSIONS + VOXEL_EXTENSIONS


def is_mesh_object(obj):
    """A document object carrying a mesh (Mesh::Feature and its kin)."""
    return obj is not None and obj.isDerivedFrom("Mesh::Feature")


def arrays_from_mesh(mesh):
    """(vertices float (n, 3), triangles int64 (m, 3)) of a Mesh.Mesh or a Mesh::Feature, in
    global coordinates (a feature's Placement applied), as csgfit.fit_mesh takes them."""
    import numpy as np

    if hasattr(mesh, "Mesh"):
        # A feature's Mesh property already carries the object's Placement.
        mesh = mesh.Mesh
    points, facets = mesh.Topology  # points with the mesh's placement applied
    vertices = np.array([(p.x, p.y, p.z) for p in points], dtype=np.float64).reshape(-1, 3)
    triangles = np.array(facets, dtype=np.int64).reshape(-1, 3)
    return vertices, triangles
