"""Many bodies: 300 knots and spheres (two shared meshes) thrown and spinning past a thin static
plate in one step; every pair's first contact, the earliest, and what sampling the step at 100
poses sees. The full simulation that never tunnels is `tocsin rain` (make demo)."""

import numpy as np

import tocsin

rng = np.random.default_rng(7)
knot = tocsin.Mesh.torus_knot(120, 10)  # bounding radius about 3.4
ball = tocsin.Mesh.sphere(1.5, 12, 16)
plate = tocsin.Mesh.plate(400.0, 4)  # zero thickness, z = 0

world = tocsin.World()
world.add_static(plate, np.eye(4))
n = 300
starts, ends = np.repeat(np.eye(4)[None], n, axis=0), np.repeat(np.eye(4)[None], n, axis=0)
for k in range(n):
    world.add_body(knot if k % 2 else ball, np.eye(4))
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    angle = rng.uniform(0, 3.0)
    kx = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    turn = np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx
    # On a grid 12 apart (a knot's radius is about 3.4): no two bodies touch at the start.
    starts[k, :3, 3] = [12.0 * (k % 18) - 102.0, 12.0 * (k // 18) - 102.0, rng.uniform(5, 40)]
    ends[k, :3, :3] = turn
    ends[k, :3, 3] = starts[k, :3, 3] + [rng.uniform(-5, 5), rng.uniform(-5, 5), -rng.uniform(0, 400)]
world.set_motions(list(range(1, n + 1)), starts, ends, kind="screw")
print(f"{len(world)} bodies sharing {world.num_meshes} meshes")

contacts = world.first_contacts()
plate_hits = [c for c in contacts if c.body1 == 0]
print(f"{len(world.candidate_pairs())} candidate pairs, {len(contacts)} contacts, "
      f"{len(plate_hits)} of them with the plate")
first = world.earliest_contact()
if first is not None:
    print(f"earliest: bodies {first.body1} and {first.body2} at t = {first.time:.6f}, "
          f"normal {np.round(first.contact.normal, 3)}")

# Sampling 101 poses of the step: how many of the plate hits does it see at all?
seen = set()
for t in np.linspace(0.0, 1.0, 101):
    for i, j in world.colliding_pairs(t=t):
        seen.add((int(i), int(j)))
missed = [c for c in plate_hits if (c.body1, c.body2) not in seen]
print(f"plate hits that 101 sampled poses never see: {len(missed)} of {len(plate_hits)}")
