"""`adbgen reproduce`'s two-plane part: its measures on synthetic runs."""

import numpy as np
import pytest

from adbgen.families.two_plane.science import reproduce as rtp
from adbgen.families.two_plane.science import runs as tr


def _run(spin, speeds):
    t = np.arange(len(spin), dtype=float)
    speeds = np.asarray(speeds, float)
    return tr.RunUp("x", 0.1, t, np.asarray(spin, float), speeds, speeds, t, speeds[:, -1], float(spin[-1]))


def test_stall_speed_is_the_plateau_while_the_balls_lag():
    spin = np.linspace(0, 3, 301)
    ball = np.minimum(spin, 0.99)  # stall just below 1
    ball[250:] = spin[250:]  # caught up
    assert rtp.stall_speed(_run(spin, np.tile(ball, (4, 1)))) == pytest.approx(0.99)
    assert rtp.stall_speed(_run(spin, np.tile(spin, (4, 1)))) is None


def test_synchronised_from_is_the_last_time_a_ball_lags():
    spin = np.full(10, 2.0)
    balls = np.tile(spin, (4, 1))
    balls[2, :6] = 1.0
    assert tr.synchronised_from(_run(spin, balls)) == 6.0
    balls[2, -1] = 1.9
    assert tr.synchronised_from(_run(spin, balls)) is None
