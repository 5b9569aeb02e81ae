"""Every public callable of the package called with seeded random bad arguments (positional and
keyword): whatever comes back, the only exceptions are the package's own (TocsinError) or
TypeError for an argument of the wrong type, and nothing crashes the process. The twenty-sixth
session's 90,000 such calls found two defects (an OverflowError for a negative body index, an
AttributeError from the module's world and robot functions), fixed; this runs a bounded share."""

import inspect
import os
import random
import warnings

import numpy as np

import tocsin


def _pool(box, knot, motion):
    nan_pose = np.eye(4)
    nan_pose[0, 3] = np.nan
    scaled = np.eye(4)
    scaled[0, 0] = 2.0
    return [
        None, "abc", "", -1, 0, 1, 2**70, 1e308, float("nan"), float("inf"), -0.0, True, 1j, b"bytes",
        np.eye(4), np.zeros((4, 4)), nan_pose, scaled, np.eye(4).astype(">f8"), np.eye(8)[::2, ::2],
        np.eye(4, dtype=np.int64), np.eye(4, dtype=np.float32), np.zeros((0, 4, 4)), np.ones((3, 4, 4)),
        np.zeros((3, 3)), np.array(1.0), np.array([1, 2, 3]), np.array([[0, 1, 2]]), np.zeros((2, 3)),
        np.array([np.nan, 0, 0]), np.array(["a"]), [], [[]], {}, object(), (1, 2, 3), [0.0, 0.0, 1.0],
        box, knot, motion, "/nonexistent.obj", 1e-3, 5, 0.5, -2.0,
    ]


def _callables(instances):
    out = []
    for name in sorted(dir(tocsin)):
        if name.startswith("_") or name == "plot_contact":
            continue
        obj = getattr(tocsin, name)
        if inspect.isclass(obj):
            if issubclass(obj, BaseException):
                continue
            if issubclass(obj, tuple):
                # Result tuples: their methods are the tuple's own (index, count).
                continue
            out.append((name, obj))
            for attr in sorted(dir(obj)):
                if attr.startswith("_"):
                    continue
                static = inspect.getattr_static(obj, attr, None)
                inst = instances.get(name)
                if isinstance(static, (staticmethod, classmethod)) or inst is None:
                    member = getattr(obj, attr)
                else:
                    member = getattr(inst, attr)
                if callable(member):
                    out.append((f"{name}.{attr}", member))
        elif callable(obj):
            out.append((name, obj))
    return out


def test_bad_arguments_raise_only_the_package_errors_or_type_errors():
    import pybullet_data

    rng = random.Random(2026)
    box = tocsin.Mesh.box([0.5, 0.5, 0.5])
    knot = tocsin.Mesh.torus_knot(40, 6)
    motion = tocsin.Motion.translation(np.eye(4), np.eye(4))
    world = tocsin.World()
    world.add_body(box, motion)
    world.add_static(knot, np.eye(4))
    robot = tocsin.Robot.from_urdf(os.path.join(pybullet_data.getDataPath(), "franka_panda/panda.urdf"))
    instances = {"Mesh": box, "Motion": motion, "World": world, "Robot": robot, "Scene": tocsin.Scene()}
    pool = _pool(box, knot, motion)
    escaped = {}
    calls = 0
    for name, target in _callables(instances):
        try:
            keywords = [
                p.name
                for p in inspect.signature(target).parameters.values()
                if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD) and p.default is not p.empty
            ]
        except (TypeError, ValueError):
            keywords = []
        for arity in range(6):
            for _ in range(12 if arity else 1):
                args = [rng.choice(pool) for _ in range(arity)]
                kwargs = {k: rng.choice(pool) for k in keywords if rng.random() < 0.3}
                calls += 1
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        target(*args, **kwargs)
                except (tocsin.TocsinError, TypeError):
                    pass
                except ValueError as e:
                    # numpy 1.x converts a one-element array to a float through its
                    # __float__, and Python's own conversion of a string in it fails with
                    # this ValueError before tocsin sees the value (numpy 2 raises TypeError).
                    if not str(e).startswith("could not convert"):
                        escaped.setdefault((name, "ValueError"), (str(e)[:200], [repr(a)[:60] for a in args], kwargs))
                except Exception as e:  # noqa: BLE001 - the point of the test
                    escaped.setdefault((name, type(e).__name__), (str(e)[:200], [repr(a)[:60] for a in args], kwargs))
    assert calls > 3000
    assert not escaped, "\n".join(f"{k}: {v}" for k, v in escaped.items())

