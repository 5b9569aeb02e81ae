"""Rigid-body planning in SE(3) with OMPL's RRT-Connect (`examples/ompl_rigid.py`'s problem: a
knot through a slot in a wall), each edge checked exactly by `tocsin.motion_is_free` or by
OMPL's own discrete motion validator at 1% and 0.1% of the space's extent (states checked with
`tocsin.collide` either way). Per run (OMPL's generator seeded once, then the runs follow each
other): planning time, states and edges checked, and whether every edge of the plan is really
free: `tocsin.motion_is_free_batch` (exact; an edge closer than half the tolerance counts as
blocked), then each blocked edge sampled at 20,001 poses with `tocsin.collide` (confirmed: the
meshes intersect there).

    python bench/ompl_rigid.py [--runs 10]
"""

import argparse
import importlib.util
import pathlib
import statistics

import numpy as np

import tocsin
from _common import machine_line

ROOT = pathlib.Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("ompl_rigid", ROOT / "examples" / "ompl_rigid.py")
example = importlib.util.module_from_spec(spec)
spec.loader.exec_module(example)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=10)
    args = parser.parse_args()
    modes = [("tocsin motion_is_free (exact)", True, None), ("OMPL discrete, 1%", False, 0.01), ("OMPL discrete, 0.1%", False, 0.001)]
    rows = {label: [] for label, _, _ in modes}
    example.ou.RNG.setSeed(1)
    for _ in range(args.runs):
        for label, exact, resolution in modes:
            _, _, poses, solved, seconds, counts = example.plan(exact, resolution or 0.01)
            free = tocsin.motion_is_free_batch(example.body, poses[:-1], poses[1:], example.wall, np.eye(4), kind="interp")
            blocked = np.flatnonzero(~free.free)
            confirmed = sum(
                any(
                    tocsin.collide(example.body, tocsin.Motion.interp(poses[k], poses[k + 1]).pose_at(t), example.wall, np.eye(4))
                    for t in np.linspace(0.0, 1.0, 20001)
                )
                for k in blocked
            )
            rows[label].append((solved, seconds, counts["states"], counts["edges"], len(blocked), confirmed, len(poses) - 1))
    print(machine_line() + f"; {args.runs} runs of RRT-Connect per row")
    print()
    print("| edge check | solved | median planning time (s) | median states checked | median exact edge checks | plans with a blocked edge | blocked edges (confirmed by samples) / all |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for label, _, _ in modes:
        r = rows[label]
        solved = sum(x[0] for x in r)
        bad = sum(1 for x in r if x[4] > 0)
        blocked, confirmed, edges = (sum(x[i] for x in r) for i in (4, 5, 6))
        print(
            f"| {label} | {solved}/{len(r)} | {statistics.median(x[1] for x in r):.2f} | "
            f"{statistics.median(x[2] for x in r):.0f} | {statistics.median(x[3] for x in r):.0f} | "
            f"{bad} | {blocked} ({confirmed}) / {edges} |"
        )


if __name__ == "__main__":
    main()
