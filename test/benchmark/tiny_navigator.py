"""A tiny external navigator for the plug-in test: turn to the goal and drive straight at it."""

import math


class StraightToGoal:
    """Implements the benchmark's navigator protocol with no map at all."""

    def __init__(self, config):
        self.max_speed = config.follower.max_linear_speed
        self.goal = None
        self.steps = 0

    def set_goal(self, x, y):
        """Take the goal [m]."""
        self.goal = (x, y)

    def step(self, stamp, pose, ranges, angle_min, angle_increment, range_min, range_max):
        """Return ``(linear, angular)``: turn to the goal, then drive at it."""
        self.steps += 1
        heading = math.atan2(self.goal[1] - pose[1], self.goal[0] - pose[0])
        error = math.remainder(heading - pose[2], math.tau)
        linear = self.max_speed * max(0.0, math.cos(error)) if abs(error) < 0.5 else 0.0
        return linear, max(-1.0, min(1.0, 2.0 * error))


class NoStep:
    """Lacks ``step``: not a navigator."""

    def set_goal(self, x, y):
        """Take the goal."""


class StandStill:
    """Stands where it starts: whatever touches it walked into it."""

    def __init__(self, config):
        self.goal = None

    def set_goal(self, x, y):
        """Take the goal (and never go there)."""
        self.goal = (x, y)

    def step(self, stamp, pose, ranges, angle_min, angle_increment, range_min, range_max):
        """Return ``(0, 0)``."""
        return 0.0, 0.0
