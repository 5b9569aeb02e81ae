"""Poses for the tests: a rotation about an axis with a translation, as a 4x4 array."""

import numpy as np


def turn(axis, angle, t):
    """The pose turning by `angle` (radians) about `axis` (any length), then moved by `t`."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    p = np.eye(4)
    p[:3, :3] = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    p[:3, 3] = t
    return p
