"""
A unicycle robot driven by the core ``Navigator`` through ray-cast scans of a truth grid.

The scripted scenes of the navigator tests (``test/core/test_not_getting_stuck.py``,
``test/core/test_give_way.py``) build a small ground-truth grid at 5 cm with `solid` and
`carve` and step a `Robot` through it at 10 Hz.
"""

import math

from dpn_navigator.core import NavigatorStatus
import numpy as np
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN, ray_cast

TRUTH_RES = 0.05
RANGE_MAX = 10.0
DT = 0.1


def solid(width, height):
    """Return a ground-truth grid at 5 cm, all wall."""
    return np.ones((int(round(height / TRUTH_RES)), int(round(width / TRUTH_RES))), dtype=bool)


def carve(occupied, x0, y0, x1, y1, value=False):
    """Set the box [x0, x1] x [y0, y1] [m] free (or wall with ``value``)."""
    occupied[int(round(y0 / TRUTH_RES)):int(round(y1 / TRUTH_RES)),
             int(round(x0 / TRUTH_RES)):int(round(x1 / TRUTH_RES))] = value


class Robot:
    """A unicycle robot driven by a navigator through ray-cast scans of a truth grid."""

    def __init__(self, navigator, occupied, pose, stamp=0.0):
        self.navigator = navigator
        self.occupied = occupied
        self.pose = tuple(pose)
        self.stamp = stamp
        self.travelled = 0.0
        self.trace = [self.pose]
        self.outputs = []

    def step(self):
        x, y, yaw = self.pose
        ranges = ray_cast(self.occupied, self.pose, TRUTH_RES, RANGE_MAX)
        out = self.navigator.step(self.stamp, self.pose, ranges, ANGLE_MIN, ANGLE_INCREMENT,
                                  RANGE_MIN, RANGE_MAX)
        v, w = out.command.linear, out.command.angular
        new = (x + v * math.cos(yaw) * DT, y + v * math.sin(yaw) * DT, yaw + w * DT)
        assert not self.occupied[int(new[1] / TRUTH_RES), int(new[0] / TRUTH_RES)], new
        self.travelled += math.dist(new[:2], (x, y))
        self.pose = new
        self.trace.append(new)
        self.outputs.append(out)
        self.stamp += DT
        return out

    def run_until(self, seconds, done=None):
        """Step for at most ``seconds``; stop early at the goal or when ``done(self)``."""
        for _ in range(int(round(seconds / DT))):
            out = self.step()
            if out.status is NavigatorStatus.GOAL_REACHED or (done is not None and done(self)):
                return out
        return self.outputs[-1]
