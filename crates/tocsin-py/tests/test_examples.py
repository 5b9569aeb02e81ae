"""Every script in examples/ runs and prints what it promises."""

import pathlib
import subprocess
import sys

import pytest

EXAMPLES = pathlib.Path(__file__).resolve().parents[3] / "examples"
EXPECT = {
    "distance.py": "collide: False",
    "time_of_contact.py": "contact at t =",
    "batch_path.py": "first blocked segment",
    "real_mesh.py": "triangles",
    "robot_plate.py": "tocsin: contact",
    "ompl_planning.py": "every edge of the path is free: True",
    "ompl_rigid.py": "every edge of the path is free: True",
    "many_bodies.py": "plate hits that 101 sampled poses never see",
}


@pytest.mark.parametrize("script", sorted(EXPECT))
def test_example_runs(script):
    out = subprocess.run([sys.executable, str(EXAMPLES / script)], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert EXPECT[script] in out.stdout, out.stdout


def test_every_example_is_tested():
    assert {p.name for p in EXAMPLES.glob("*.py")} == set(EXPECT)
