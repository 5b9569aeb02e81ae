"""Checking a planned path: 500 segments of a knot's motion, in parallel, in one call."""

import time

import numpy as np

import tocsin

knot = tocsin.Mesh.torus_knot(344, 16)
k = 500
ts = np.linspace(0.0, 1.0, k + 1)
waypoints = np.tile(np.eye(4), (k + 1, 1, 1))
waypoints[:, 0, 3] = 16.0 * ts - 8.0  # sweep through the other knot along x
waypoints[:, 1, 3] = 0.4 * np.sin(6 * ts)
for p, t in zip(waypoints, ts):
    a = 1.5 * t
    p[:3, :3] = [[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]]

start = time.perf_counter()
batch = tocsin.time_of_contact_batch(knot, waypoints[:-1], waypoints[1:], knot, kind="interp")
elapsed = time.perf_counter() - start
hit = np.flatnonzero(batch.status != "none")
print(f"{k} segments checked in {elapsed * 1e3:.1f} ms ({k / elapsed:.0f} segments/s)")
if hit.size:
    first = hit[0]
    print(f"first blocked segment: {first}, contact at its t = {batch.time[first]:.4f}, point {batch.point1[first].round(3)}")
else:
    print("the path is free")
