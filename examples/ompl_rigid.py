"""Rigid-body planning in SE(3) with OMPL's RRT-Connect, tocsin as the state validity checker
and as the exact motion validator: a torus knot (flat: 6.1 by 6.4 across, 2.8 thick) flies
through a slot 8 wide and 4 high in a wall, and turns a quarter turn on the other side.

OMPL interpolates an SE(3) state linearly in position and along the shorter great arc in
rotation; tocsin's `Motion.interp` about the body origin is the same path, so
`tocsin.motion_is_free` answers OMPL's checkMotion exactly (no resolution to tune). The plan's
edges are checked again in one call (`motion_is_free_batch`) and against 2,001 samples each.
"""

import time

import numpy as np
import ompl.base as ob
import ompl.geometric as og
import ompl.util as ou

import tocsin

ou.setLogLevel(ou.LOG_WARN)

body = tocsin.Mesh.torus_knot(120, 8)  # bounding radius about 6
still = tocsin.Motion.stationary(np.eye(4))


def wall_with_slot(half=30.0, slot=(4.0, 2.0), thick=1.0):
    """One soup of four boxes: a wall in the plane x = 0 with a slot of half sizes `slot` (y, z)."""
    sy, sz = slot
    parts = []
    for cy, cz, hy, hz in [
        (0.0, (half + sz) / 2, half, (half - sz) / 2),  # above the slot
        (0.0, -(half + sz) / 2, half, (half - sz) / 2),  # below
        ((half + sy) / 2, 0.0, (half - sy) / 2, sz),  # right
        (-(half + sy) / 2, 0.0, (half - sy) / 2, sz),  # left
    ]:
        box = tocsin.Mesh.box([thick, hy, hz])
        parts.append((box.vertices + [0.0, cy, cz], box.triangles))
    vertices, triangles, offset = [], [], 0
    for v, t in parts:
        vertices.append(v)
        triangles.append(t + offset)
        offset += len(v)
    return tocsin.Mesh(np.concatenate(vertices), np.concatenate(triangles))


wall = wall_with_slot()


def pose(state):
    """The 4x4 pose of an SE(3) state (position, unit quaternion)."""
    r = state.rotation()
    x, y, z, w = r.x, r.y, r.z, r.w
    p = np.eye(4)
    p[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    p[:3, 3] = [state.getX(), state.getY(), state.getZ()]
    # OMPL's quaternions are unit to float rounding; tocsin asks for rigid poses within 1e-6.
    return tocsin.orthonormalize(p)


class ExactMotionValidator(ob.MotionValidator):
    """OMPL's checkMotion(s1, s2) answered exactly by tocsin."""

    def __init__(self, si, counts):
        super().__init__(si)
        self.counts = counts

    def checkMotion(self, s1, s2, *last_valid):
        self.counts["edges"] += 1
        return tocsin.motion_is_free(body, tocsin.Motion.interp(pose(s1), pose(s2)), wall, still)


def plan(exact=True, resolution=0.01, budget=60.0):
    """RRT-Connect from the start to the goal, each edge checked exactly by tocsin (`exact`) or
    by OMPL's own sampling at `resolution` of the space's extent. Returns the space, the path's
    states and poses, whether it was solved, the seconds and the counts of checks."""
    counts = {"states": 0, "edges": 0}

    def is_valid(state):
        counts["states"] += 1
        return not tocsin.collide(body, pose(state), wall, np.eye(4))

    space = ob.SE3StateSpace()
    bounds = ob.RealVectorBounds(3)
    for i, (lo, hi) in enumerate([(-22.0, 22.0), (-6.0, 6.0), (-6.0, 6.0)]):
        bounds.setLow(i, lo)
        bounds.setHigh(i, hi)
    space.setBounds(bounds)
    si = ob.SpaceInformation(space)
    si.setStateValidityChecker(is_valid)
    if exact:
        si.setMotionValidator(ExactMotionValidator(si, counts))
    else:
        si.setStateValidityCheckingResolution(resolution)
    si.setup()
    start, goal = space.allocState(), space.allocState()
    start.setXYZ(-20.0, 0.0, 0.0)
    start.rotation().setIdentity()
    goal.setXYZ(20.0, 0.0, 0.0)
    goal.rotation().setAxisAngle(1.0, 0.0, 0.0, np.pi / 2)
    assert is_valid(start) and is_valid(goal)
    problem = ob.ProblemDefinition(si)
    problem.setStartAndGoalStates(start, goal)
    planner = og.RRTConnect(si)
    planner.setProblemDefinition(problem)
    planner.setup()
    began = time.perf_counter()
    solved = planner.solve(budget)
    elapsed = time.perf_counter() - began
    path = problem.getSolutionPath()
    states = [path.getState(i) for i in range(path.getStateCount())]
    poses = np.array([pose(s) for s in states])
    return space, states, poses, bool(solved), elapsed, counts


def main():
    ou.RNG.setSeed(7)  # before OMPL draws its first number: the same plan every run
    start, goal = np.eye(4), np.eye(4)
    start[0, 3], goal[0, 3] = -20.0, 20.0
    goal[1:3, 1:3] = [[0.0, -1.0], [1.0, 0.0]]
    # The straight motion turns the knot on its way through the slot and hits the wall.
    straight = tocsin.Motion.interp(start, goal)
    print(f"straight motion free: {tocsin.motion_is_free(body, straight, wall, still)}")
    space, states, poses, solved, elapsed, counts = plan()
    print(f"RRT-Connect: {solved} in {elapsed:.2f} s, {counts['states']} states and {counts['edges']} edges checked")
    print(f"{len(poses)} waypoints")
    batch = tocsin.motion_is_free_batch(body, poses[:-1], poses[1:], wall, np.eye(4), kind="interp")
    sampled = [
        any(
            tocsin.collide(body, tocsin.Motion.interp(a, b).pose_at(t), wall, np.eye(4))
            for t in np.linspace(0.0, 1.0, 2001)
        )
        for a, b in zip(poses[:-1], poses[1:])
    ]
    # OMPL's own interpolation along each edge is the path tocsin checked.
    between = space.allocState()
    gap = 0.0
    for i in range(len(states) - 1):
        motion = tocsin.Motion.interp(poses[i], poses[i + 1])
        for t in (0.25, 0.5, 0.75):
            space.interpolate(states[i], states[i + 1], t, between)
            gap = max(gap, np.abs(pose(between) - motion.pose_at(t)).max())
    print(f"OMPL's interpolation and Motion.interp agree to {gap:.1e}")
    free = solved and batch.free.all() and batch.decided.all() and not any(sampled) and gap < 1e-6
    print(f"every edge of the path is free: {free}")


if __name__ == "__main__":
    main()
