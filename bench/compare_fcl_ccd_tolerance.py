"""What a time of contact's tolerance costs, beside FCL's 100-sample sampler, in one run.

The passes through of `compare_fcl_ccd.py`'s cells (the same seeded queries: body 1 driven
5 bounding radii through body 2, which stays at the identity), timed as
`_common.sweeps` does (each method a loop over the passes, the loops taking turns,
three rounds, median per pass), objects built before the timer:
`tocsin.time_of_contact` at tolerances of 1e-3 (the default), 1e-2 and 5e-2 of the bounding
radius R, each with the closest points (the default) and with `contact_pair=True`;
`tocsin.distance` at the start (the issue's yardstick); FCL's naive solver at 100 samples.

The sampler steps 1/100 of the motion, 0.05 R of the centre's travel here: its answer is a sample after the
first contact, as coarse as a 5e-2 R tolerance in space, with no bound on how far the meshes
have gone into each other. Accuracy against the oracle of `compare_fcl_ccd.py` (1,000
exact collision samples refined by bisection): how many answers are late (after the first
collision) and by how much at most, and how many are early, for tocsin at 5e-2 R and for the
sampler. Near misses are left out: at 5e-2 R a pass at 1% of R is a contact by the
tolerance's contract (closer than half of it).

Usage: python bench/compare_fcl_ccd_tolerance.py [--models ...] [--out FILE]
"""

import argparse
import statistics
import zlib

import numpy as np

import tocsin
from _common import fcl_model, machine_line, models, sweeps, write
from compare_fcl_ccd import KINDS, fcl_call, oracle, queries

import fcl

FRACTIONS = (1e-3, 1e-2, 5e-2)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", default="knot2.8k,knot34k,bunny,panda_link1")
    ap.add_argument("--out", default="bench/out/fcl_ccd_tolerance.md")
    args = ap.parse_args()
    still = np.eye(4)
    stay = tocsin.Motion.stationary(still)
    lines = [
        f"{machine_line()}, python-fcl {getattr(fcl, '__version__', '?')}; 30 passes per cell.",
        "",
        "| model | motion | distance at the start (us) | "
        + " | ".join(f"time of contact at {f:g} R: closest points / contact pair (us)" for f in FRACTIONS)
        + " | fcl naive 100 (us) | tocsin at 5e-2 R: late, early, largest lateness | fcl naive 100: late, early, largest lateness |",
        "|---|---|" + "---:|" * (len(FRACTIONS) + 4),
    ]
    for name, mesh in models(args.models.split(",")).items():
        fm, r = fcl_model(mesh), mesh.bounding_radius
        for kind, fcl_kind in KINDS.items():
            rng = np.random.default_rng(zlib.crc32(f"{name}/{kind}".encode()))
            qs = queries(mesh, kind, 30, 20, rng)[:30]
            firsts = [oracle(mesh, mo) for mo, _, _ in qs]
            req = fcl.ContinuousCollisionRequest(
                num_max_iterations=100, ccd_motion_type=fcl_kind, ccd_solver_type=fcl.CCDSolverType.CCDC_NAIVE
            )
            o2 = fcl.CollisionObject(fm, fcl.Transform())

            def toc(mo, fraction, pair):
                def run():
                    c = tocsin.time_of_contact(mesh, mo, mesh, stay, tolerance=fraction * r, contact_pair=pair)
                    return None if c is None else c.time

                return run

            calls = {(f, p): [toc(mo, f, p) for mo, _, _ in qs] for f in FRACTIONS for p in (False, True)}
            calls["distance"] = [lambda s=s: tocsin.distance(mesh, s, mesh, still).distance for _, s, _ in qs]
            calls["fcl"] = [fcl_call(fm, o2, req, s, e) for _, s, e in qs]
            times, answered = sweeps(calls)
            med = {label: statistics.median(t) * 1e6 for label, t in times.items()}

            def accuracy(label):
                answers = answered[label]
                offsets = [a - f for a, f in zip(answers, firsts) if a is not None and f is not None]
                late = [x for x in offsets if x > 1e-9]
                missed = sum(a is None and f is not None for a, f in zip(answers, firsts))
                early = sum(x < -1e-9 for x in offsets)
                worst = f"{max(late):.4f}" if late else "-"
                return f"{len(late)}, {early}, {worst}" + (f" ({missed} missed)" if missed else "")

            timings = " | ".join(f"{med[(f, False)]:.0f} / {med[(f, True)]:.0f}" for f in FRACTIONS)
            lines.append(
                f"| {name} | {kind} | {med['distance']:.0f} | {timings} | {med['fcl']:.0f} | "
                f"{accuracy((FRACTIONS[-1], False))} | {accuracy('fcl')} |"
            )
            print(lines[-1], flush=True)
    write(args.out, "\n".join(lines))


if __name__ == "__main__":
    main()
