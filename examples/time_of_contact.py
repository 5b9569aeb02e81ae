"""Time of contact: a knot flying and turning into another, against sampling 100 poses."""

import numpy as np

import tocsin

knot = tocsin.Mesh.torus_knot(344, 16)
start, end = np.eye(4), np.eye(4)
start[:3, 3] = [-14.0, 1.0, 0.5]
angle = np.radians(75)
end[:3, :3] = [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
end[:3, 3] = [14.0, -0.5, 0.0]
still = tocsin.Motion.stationary(np.eye(4))

for kind in ("translation", "interp", "screw"):
    if kind == "translation":
        motion = tocsin.Motion.translation(start, np.block([[start[:3, :3], end[:3, 3:]], [0, 0, 0, 1]]))
    else:
        motion = getattr(tocsin.Motion, kind)(start, end)
    c = tocsin.time_of_contact(knot, motion, knot, still)
    sampled = next((k / 100 for k in range(101) if tocsin.collide(knot, motion.pose_at(k / 100), knot, np.eye(4))), None)
    if c is None:
        print(f"{kind:12s} no contact (sampling: {sampled})")
    else:
        print(f"{kind:12s} contact at t = {c.time:.6f} ({c.status}, {c.iterations} iterations), "
              f"distance {c.distance:.2e}, normal {c.normal.round(3)}; first of 100 samples: {sampled}")
