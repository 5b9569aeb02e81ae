"""Distance and collision between two torus knots (34,000 triangles each)."""

import numpy as np

import tocsin

knot = tocsin.Mesh.torus_knot(680, 25)
pose2 = np.eye(4)
pose2[:3, 3] = [7.0, 0.2, 0.1]  # 4x4 rigid transform, world frame

r = tocsin.distance(knot, np.eye(4), knot, pose2)
print(f"distance {r.distance:.6f} between {r.point1.round(4)} and {r.point2.round(4)}")
print(f"triangles {r.triangle1} and {r.triangle2}")
print("collide:", tocsin.collide(knot, np.eye(4), knot, pose2))
print("within 0.5:", tocsin.within_distance(knot, np.eye(4), knot, pose2, 0.5))
