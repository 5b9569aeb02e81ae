"""A robot arm sweeping its fingers through a 1 mm plate, which a sampler misses.

The Franka Panda (collision meshes from pybullet_data, vendored in data/franka_panda) turns its
first joint from -2.8 to 2.8 rad; a 1 mm plate stands in the fingers' path, reaching 3 mm above
their lowest point. Checking the segment at 101 configurations (OMPL's default resolution is 1%
of the space's extent) finds no collision; tocsin's exact segment check finds the contact.
"""

import pathlib
import time

import numpy as np

import tocsin

ROOT = pathlib.Path(__file__).resolve().parents[1]
robot = tocsin.Robot.from_urdf(ROOT / "data" / "franka_panda" / "panda.urdf")
q0 = np.array([-2.8, 0.3, 0.0, -2.0, 0.0, 2.4, 0.8, 0.04])
q1 = q0.copy()
q1[0] = 2.8

# Where the fingers are half way: the plate goes there, across their path.
names = robot.object_names
poses = robot.object_poses(0.5 * (q0 + q1))
fingers = np.vstack(
    [
        robot.object_mesh(n).vertices @ poses[names.index(n)][:3, :3].T + poses[names.index(n)][:3, 3]
        for n in ("panda_leftfinger", "panda_rightfinger")
    ]
)
centre, lowest = fingers.mean(axis=0), fingers[:, 2].min()
radial = np.array([centre[0], centre[1], 0.0]) / np.hypot(centre[0], centre[1])
pose = np.eye(4)
pose[:3, 0] = [-radial[1], radial[0], 0.0]  # the plate's thin side along the fingers' motion
pose[:3, 1] = -radial
pose[:3, 3] = [centre[0], centre[1], lowest + 0.003 - 0.2]
scene = tocsin.Scene()
scene.add("plate", tocsin.Mesh.box([0.0005, 0.2, 0.2]), pose)

samples = np.array([q0 + t * (q1 - q0) for t in np.linspace(0.0, 1.0, 101)])
hit = robot.check_configurations(samples, scene).any()
print(f"sampler at 1%: {'collision' if hit else 'free'} (101 configurations checked exactly)")
start = time.perf_counter()
contact = robot.time_of_contact(q0, q1, scene)
elapsed = time.perf_counter() - start
if contact is None:
    print("tocsin: free")
else:
    print(
        f"tocsin: contact at t = {contact.time:.5f} between {contact.object1} and {contact.object2}, "
        f"distance {contact.distance:.2e} m, point {np.round(contact.point2, 4)} ({elapsed * 1e3:.2f} ms)"
    )
print(f"path_is_free: {robot.path_is_free(q0, q1, scene)}")
