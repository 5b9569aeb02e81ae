"""plot_contact writes a PNG of the contact (needs matplotlib, installed by make test)."""

import numpy as np
import pytest

import tocsin


def test_plot_contact_writes_png(tmp_path):
    knot = tocsin.Mesh.torus_knot(60, 6)
    start, end = np.eye(4), np.eye(4)
    start[:3, 3], end[:3, 3] = [-10, 0.5, 0], [10, 0, 0]
    motion = tocsin.Motion.interp(start, end)
    c = tocsin.time_of_contact(knot, motion, knot, tocsin.Motion.stationary(np.eye(4)))
    assert c is not None
    out = tmp_path / "contact.png"
    fig = tocsin.plot_contact(knot, motion.pose_at(c.time), knot, np.eye(4), c, path=str(out))
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000
    assert "time of contact" in fig.axes[0].get_title()
    # Without a result it computes the distance itself.
    far = np.eye(4)
    far[0, 3] = 9.0
    fig = tocsin.plot_contact(knot, np.eye(4), knot, far, path=str(tmp_path / "d.png"))
    assert fig.axes[0].get_title().startswith("distance")
