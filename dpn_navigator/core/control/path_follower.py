"""
A path follower for a differential-drive robot: pose and path in, ``(v, omega)`` out.

The robot steers toward a look-ahead point on the path: the first path point at least
``lookahead_distance`` ahead of the path point closest to the robot (or the goal), but never
past a corner: where the path's heading has turned by more than ``corner_angle`` since the
closest point, the look-ahead point stops at the corner. The robot thus drives to a sharp
corner and turns there, on the path, instead of cutting inside it, which in a corridor as
narrow as the robot's turning circle would bring its corners to the wall. The angular
speed is proportional to the heading error; the robot turns in place when the error is larger
than ``turn_in_place_angle``, slows down as the error grows and as the goal nears, and stops
inside ``goal_tolerance`` less ``goal_approach_margin`` (0 by default, the paper's rule: it stops
at the tolerance's edge).

"""

from dataclasses import dataclass
import math

import numpy as np

from ..pose2d import wrap_angle
from ..settings import setting


@dataclass(frozen=True)
class FollowerConfig:
    """
    Limits and gains of the path follower; defaults suit a Clearpath Husky A200.

    Every field carries its unit, range and meaning (``settings.settings_of(FollowerConfig)``);
    the gains in more words:

    Attributes
    ----------
    heading_gain : float
        Angular speed per radian of heading error [1/s].
    turn_in_place_angle : float
        Heading error above which the robot stops to turn [rad].
    slowdown_distance : float
        Within this distance of the goal, the speed falls linearly toward zero [m].
    corner_angle : float
        A turn of the path's heading larger than this is a corner the look-ahead point does
        not pass [rad]; larger than 45 degrees, so that the steps of an 8-connected grid path
        are not corners.
    goal_approach_margin : float
        The robot drives on until it is this far inside ``goal_tolerance`` by its own pose
        estimate [m], so that a localisation error up to this size still leaves it inside the
        tolerance of the true goal; 0 stops at the tolerance's edge (the paper).

    """

    max_linear_speed: float = setting(1.0, 'm/s', "forward speed limit (the Husky's top speed)",
                                      0.01, 5.0)
    max_angular_speed: float = setting(1.5, 'rad/s', 'turn rate limit', 0.01, 10.0)
    lookahead_distance: float = setting(0.6, 'm', 'how far ahead on the path the robot aims',
                                        0.1, 10.0)
    goal_tolerance: float = setting(0.3, 'm', 'distance to the goal that counts as reached',
                                    0.01, 5.0)
    heading_gain: float = setting(2.0, '1/s', "the follower's turn rate per radian of heading "
                                  'error', 0.01, 100.0)
    turn_in_place_angle: float = setting(
        0.6, 'rad', 'heading error above which the robot stops to turn in place', 0.01, math.pi)
    slowdown_distance: float = setting(
        1.5, 'm', 'within this distance of the goal the speed falls linearly toward zero',
        0.01, 100.0)
    corner_angle: float = setting(
        1.0, 'rad', "a turn of the path's heading larger than this is a corner the look-ahead "
        'point does not pass (above 45 degrees, the steps of a grid path)', 0.8, math.pi)
    goal_approach_margin: float = setting(
        0.0, 'm', 'the robot drives on until it is this far inside the goal tolerance, so that '
        'a localisation error up to this size still ends inside the tolerance of the true goal '
        '(0: stop at the edge, the paper)', 0.0, 5.0)

    def __post_init__(self):
        for name in ('max_linear_speed', 'max_angular_speed', 'lookahead_distance',
                     'goal_tolerance', 'heading_gain', 'turn_in_place_angle',
                     'slowdown_distance', 'corner_angle'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        margin = self.goal_approach_margin
        if not (math.isfinite(margin) and 0.0 <= margin < self.goal_tolerance):
            raise ValueError(f'goal_approach_margin must be in [0, goal_tolerance '
                             f'{self.goal_tolerance!r}), got {margin!r}')
        if self.turn_in_place_angle > math.pi:
            raise ValueError(
                f'turn_in_place_angle must be at most pi, got {self.turn_in_place_angle!r}')


@dataclass(frozen=True)
class VelocityCommand:
    """
    A velocity command for a differential-drive base.

    Attributes
    ----------
    linear : float
        Forward speed [m/s], in ``[0, max_linear_speed]``.
    angular : float
        Turn rate, counter-clockwise positive [rad/s], in ``[-max_angular_speed,
        max_angular_speed]``.
    goal_reached : bool
        True when the robot is inside the goal tolerance (the command is then zero).
    turn : float
        For a turn in place, the heading change still to turn, counter-clockwise positive
        [rad] (``turn_sweep`` checks it); 0 otherwise.

    """

    linear: float
    angular: float
    goal_reached: bool = False
    turn: float = 0.0


STOP = VelocityCommand(0.0, 0.0)


def follow_path(pose, path_xy, config):
    """
    Compute the velocity that follows a path.

    Parameters
    ----------
    pose : (float, float, float)
        Robot base ``(x, y, yaw)`` in the map frame [m, m, rad], finite.
    path_xy : (N, 2) ndarray of float64
        Path points in the map frame [m], the last one the goal; ``N >= 1``.
    config : FollowerConfig
        Limits and gains.

    Returns
    -------
    VelocityCommand

    Raises
    ------
    ValueError
        When the path is empty or not (N, 2), or the pose is not finite.

    """
    path_xy = np.asarray(path_xy, dtype=np.float64)
    if path_xy.ndim != 2 or path_xy.shape[1] != 2 or path_xy.shape[0] == 0:
        raise ValueError(f'path_xy must be a non-empty (N, 2) array, got shape {path_xy.shape}')
    x, y, yaw = (float(v) for v in pose)
    if not all(math.isfinite(v) for v in (x, y, yaw)):
        raise ValueError(f'pose must be finite, got {pose!r}')
    goal_x, goal_y = path_xy[-1]
    to_goal = math.hypot(goal_x - x, goal_y - y)
    if to_goal <= config.goal_tolerance - config.goal_approach_margin:
        return VelocityCommand(0.0, 0.0, goal_reached=True)
    distance = np.hypot(path_xy[:, 0] - x, path_xy[:, 1] - y)
    closest = int(np.argmin(distance))
    ahead = np.flatnonzero(distance[closest:] >= config.lookahead_distance)
    target_index = closest + int(ahead[0]) if ahead.shape[0] else len(path_xy) - 1
    target = path_xy[_corner_before(path_xy, closest, target_index, config.corner_angle)]
    heading_error = wrap_angle(math.atan2(target[1] - y, target[0] - x) - yaw)
    angular = float(np.clip(config.heading_gain * heading_error,
                            -config.max_angular_speed, config.max_angular_speed))
    if abs(heading_error) > config.turn_in_place_angle:
        return VelocityCommand(0.0, angular, turn=heading_error)
    # Slow down as the heading error grows, to nearly a stop close to the turn-in-place angle
    # (a sharp corner is turned tightly, not cut), and inside the slow-down distance.
    turn_share = abs(heading_error) / config.turn_in_place_angle
    linear = config.max_linear_speed * math.cos(heading_error) * (1.0 - turn_share ** 2)
    linear *= min(1.0, to_goal / config.slowdown_distance)
    return VelocityCommand(float(np.clip(linear, 0.0, config.max_linear_speed)), angular)


def _corner_before(path_xy, first, last, corner_angle):
    """
    Return the last path index in ``[first, last]`` reached before the heading turns a corner.

    Parameters
    ----------
    path_xy : (N, 2) ndarray of float64
        The path [m].
    first, last : int
        Indices: the point closest to the robot and the look-ahead candidate.
    corner_angle : float
        [rad]

    Returns
    -------
    index : int
        ``last`` when the heading of every segment from ``first`` to ``last`` stays within
        ``corner_angle`` of the first segment's; otherwise the start of the first segment
        that does not.

    """
    if last - first < 2:
        return last
    steps = np.diff(path_xy[first:last + 1], axis=0)
    headings = np.arctan2(steps[:, 1], steps[:, 0])
    # A zero-length step has no heading of its own: it keeps the one before.
    moving = np.hypot(steps[:, 0], steps[:, 1]) > 1e-9
    headings = headings[np.maximum.accumulate(np.where(moving, np.arange(len(steps)), 0))]
    turned = np.abs(np.angle(np.exp(1j * (headings - headings[0])))) > corner_angle
    corners = np.flatnonzero(turned)
    return first + int(corners[0]) if corners.shape[0] else last
