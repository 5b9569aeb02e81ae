"""Planning with OMPL's RRT-Connect, tocsin as the state validity checker and as the exact
motion validator (no edge of the plan can pass through an obstacle between samples).

The Panda (data/franka_panda) reaches from one side of a wall with a window to the other. Each
edge RRT-Connect tries is checked by Robot.path_is_free, exactly; the final path is checked
again, edge by edge, and against 2,001 samples per edge.
"""

import pathlib
import time

import numpy as np
import ompl.base as ob
import ompl.geometric as og

import tocsin

ROOT = pathlib.Path(__file__).resolve().parents[1]
robot = tocsin.Robot.from_urdf(ROOT / "data" / "franka_panda" / "panda.urdf")
FINGERS = 0.04
ARM = 7

scene = tocsin.Scene()
for name, size, centre in [
    ("wall_low", [0.02, 0.6, 0.25], [0.45, 0.0, 0.25]),
    ("wall_high", [0.02, 0.6, 0.2], [0.45, 0.0, 1.05]),
    ("wall_left", [0.02, 0.2, 0.3], [0.45, 0.45, 0.65]),
    ("wall_right", [0.02, 0.2, 0.3], [0.45, -0.45, 0.65]),
    ("floor", [0.6, 0.6, 0.01], [0.3, 0.0, -0.02]),
]:
    pose = np.eye(4)
    pose[:3, 3] = centre
    scene.add(name, tocsin.Mesh.box(size), pose)


def full(x):
    return np.concatenate([x, [FINGERS]])


def config(state):
    return full(np.array([state[i] for i in range(ARM)]))


space = ob.RealVectorStateSpace(ARM)
bounds = ob.RealVectorBounds(ARM)
limits = robot.joint_limits
for i in range(ARM):
    bounds.setLow(i, limits[i, 0])
    bounds.setHigh(i, limits[i, 1])
space.setBounds(bounds)
si = ob.SpaceInformation(space)
counts = {"states": 0, "edges": 0}


def is_valid(state):
    counts["states"] += 1
    return not robot.in_collision(config(state), scene)


class ExactMotionValidator(ob.MotionValidator):
    """OMPL's checkMotion(s1, s2) answered exactly by tocsin (no resolution to tune)."""

    def checkMotion(self, s1, s2, *last_valid):
        counts["edges"] += 1
        return robot.path_is_free(config(s1), config(s2), scene)


si.setStateValidityChecker(is_valid)
validator = ExactMotionValidator(si)
si.setMotionValidator(validator)
si.setup()

start, goal = space.allocState(), space.allocState()
q_start = np.array([-1.2, 0.4, 0.0, -2.0, 0.0, 2.4, 0.8])
q_goal = np.array([0.0, 0.5, 0.0, -1.2, 0.0, 1.7, 0.8])
for i in range(ARM):
    start[i], goal[i] = q_start[i], q_goal[i]
assert is_valid(start) and is_valid(goal)
problem = ob.ProblemDefinition(si)
problem.setStartAndGoalStates(start, goal)
planner = og.RRTConnect(si)
planner.setProblemDefinition(problem)
planner.setup()
began = time.perf_counter()
solved = planner.solve(60.0)
elapsed = time.perf_counter() - began
print(f"RRT-Connect: {solved} in {elapsed:.2f} s, {counts['states']} states and {counts['edges']} edges checked")
path = problem.getSolutionPath()
waypoints = [config(path.getState(i)) for i in range(path.getStateCount())]
print(f"{len(waypoints)} waypoints")
edges_free = all(robot.path_is_free(a, b, scene) for a, b in zip(waypoints, waypoints[1:]))
sampled = [
    robot.check_configurations(np.array([a + t * (b - a) for t in np.linspace(0, 1, 2001)]), scene).any()
    for a, b in zip(waypoints, waypoints[1:])
]
print(f"every edge of the path is free: {edges_free and not any(sampled) and bool(solved)}")
