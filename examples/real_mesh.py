"""Loading a real mesh: the Stanford bunny shipped by pybullet_data, or a small OBJ written here."""

import os
import sys
import tempfile

import numpy as np

import tocsin

try:
    import pybullet_data

    path = os.path.join(pybullet_data.getDataPath(), "bunny.obj")
except ImportError:
    path = os.path.join(tempfile.mkdtemp(), "tetra.obj")
    with open(path, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n")

mesh = tocsin.Mesh.load(path)
print(f"{os.path.basename(path)}: {mesh.num_vertices} vertices, {mesh.num_triangles} triangles, radius {mesh.bounding_radius:.3f}")
pose = np.eye(4)
pose[0, 3] = 1.5 * mesh.bounding_radius
print(f"distance to a copy moved by 1.5 radii: {tocsin.distance(mesh, np.eye(4), mesh, pose).distance:.4f}")
try:
    tocsin.Mesh.load(path + ".missing.obj")
except tocsin.MeshFileError as e:
    print("a missing file raises tocsin.MeshFileError:", e, file=sys.stderr)
