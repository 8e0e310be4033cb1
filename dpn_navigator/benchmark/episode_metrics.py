"""
What the benchmark itself sees of an episode: its outcome and the field's standard measures.

The navigator's own report is not trusted: success is the true pose's distance to the goal
and the contact log, and the failure reason is read from the true trajectory
(`end_reason`). The measures are those the field reports (definitions and sources in
``docs/benchmark.md``): SPL (Anderson et al. 2018), the BARN score (the BARN Challenge's
``run.py``), time and path-length ratios, the clearance to moving agents and the time inside
their personal space (Arena-Rosnav), jerk and time standing still.

A `TrajectoryRecorder` is fed the true state once per scan; ``metrics`` turns it into an
`EpisodeMetrics`. Everything here is numpy, with no simulator import.

"""

from dataclasses import asdict, dataclass
import math

import numpy as np

#: The one reference speed every navigator's time limit and optimal time derive from [m/s]
#: (the Husky's top speed), whatever speed a navigator declares.
REFERENCE_SPEED = 1.0
#: Fixed part of the time limit [s]: ``TIME_LIMIT_BASE + TIME_LIMIT_FACTOR * L / v_ref``.
TIME_LIMIT_BASE = 30.0
#: Factor on the reference time of the time limit.
TIME_LIMIT_FACTOR = 3.0
#: Distance of the true base position to the goal that counts as arrived [m] (the navigators'
#: own tolerance, ``FollowerConfig.goal_tolerance``, and the BARN Challenge's 0.3 m).
GOAL_TOLERANCE = 0.3
#: Window before the end over which a failed episode's motion is judged [s].
STUCK_WINDOW = 10.0
#: Less than this distance driven within `STUCK_WINDOW` is standing (stuck) [m].
STUCK_DISTANCE = 0.5
#: Window of the oscillation test [s].
OSCILLATION_WINDOW = 30.0
#: Driven at least this far in `OSCILLATION_WINDOW` [m] ...
OSCILLATION_TRAVEL = 3.0
#: ... but ending within this distance of where the window began [m]: oscillating.
OSCILLATION_NET = 1.0
#: Speeds under which the robot stands still [m/s, rad/s].
STILL_LINEAR = 0.05
STILL_ANGULAR = 0.05
#: Personal space of a moving agent: its edge within this distance of the robot's centre [m]
#: (Hall's personal distance, 1.2 m, as Arena-Rosnav's and the social-navigation metrics use).
PERSONAL_SPACE = 1.2
#: The BARN score's optimal time is the reference time at twice ...: its clip bounds.
BARN_CLIP = (2.0, 8.0)

#: Values of the ``end_reason`` column, in the order they are tested.
END_REASONS = ('', 'collision', 'false_arrival', 'no_path', 'stuck', 'oscillating',
               'timeout_moving')


def time_limit(shortest_path):
    """Return the time limit [s] of a task whose reference shortest path is ``L`` [m]."""
    return TIME_LIMIT_BASE + TIME_LIMIT_FACTOR * shortest_path / REFERENCE_SPEED


def spl(success, shortest_path, path_length):
    """
    Return one episode's success weighted by path length (Anderson et al. 2018, eq. 1).

    ``S * L / max(P, L)``; 0 when the episode failed or has no finite shortest path.
    """
    if not success or not math.isfinite(shortest_path) or shortest_path <= 0.0:
        return 0.0
    return shortest_path / max(path_length, shortest_path)


def barn_score(success, shortest_path, time):
    """
    Return one episode's BARN Challenge score.

    ``S * OT / clip(AT, 2 OT, 8 OT)`` with the optimal time ``OT = L / v_ref`` (the challenge
    divides by the Jackal's 2 m/s; here `REFERENCE_SPEED`) and ``AT`` the time taken: 0.5 for
    arriving in twice the optimal time or sooner, 1/16 at eight times or later, 0 on failure.
    """
    if not success or not math.isfinite(shortest_path) or shortest_path <= 0.0:
        return 0.0
    optimal = shortest_path / REFERENCE_SPEED
    low, high = BARN_CLIP
    return optimal / min(max(time, low * optimal), high * optimal)


@dataclass(frozen=True)
class EpisodeMetrics:
    """
    The benchmark's view of one episode.

    Attributes
    ----------
    goal_distance : float
        Distance of the true base position to the goal at the end [m].
    judged_success : bool
        ``goal_distance <= GOAL_TOLERANCE`` before the time limit, with no contact.
    end_reason : str
        One of `END_REASONS` (see `end_reason`).
    spl, barn_score : float
        See `spl` and `barn_score`.
    time_ratio : float or None
        Time taken over the reference time ``L / v_ref``; None when the episode failed.
    path_ratio : float or None
        Distance driven over ``L``; None when the episode failed.
    min_agent_distance : float or None
        Smallest distance from the robot's centre to a moving agent's edge [m]; None with
        no agents.
    personal_space_time : float
        Time with an agent's edge within `PERSONAL_SPACE` of the robot's centre [s].
    jerk_rms, angular_jerk_rms : float
        Root mean square of the third derivative of the driven distance and of the heading,
        from the true velocities at scan rate [m/s^3, rad/s^3].
    still_time : float
        Time standing still (`STILL_LINEAR`, `STILL_ANGULAR`) [s].

    """

    goal_distance: float
    judged_success: bool
    end_reason: str
    spl: float
    barn_score: float
    time_ratio: object
    path_ratio: object
    min_agent_distance: object
    personal_space_time: float
    jerk_rms: float
    angular_jerk_rms: float
    still_time: float

    def as_row(self):
        """Return the measures as a flat dict, rounded, for the log (success has its column)."""
        row = asdict(self)
        del row['judged_success']
        for name, value in row.items():
            if isinstance(value, float):
                row[name] = round(value, 4)
        return row


#: The measures' columns, in `EpisodeMetrics` (and CSV) order (``success`` has its own).
METRIC_FIELDS = tuple(name for name in EpisodeMetrics.__dataclass_fields__
                      if name != 'judged_success')


def end_reason(times, xy, success, contacts, reported_goal, reported_no_path):
    """
    Say why an episode ended as the benchmark sees it.

    Tested in this order: ``''`` (success); ``collision`` (any contact event);
    ``false_arrival`` (the navigator reported the goal reached but the true pose is not within
    `GOAL_TOLERANCE`); then the motion over the last `STUCK_WINDOW` seconds: less than
    `STUCK_DISTANCE` driven is ``no_path`` when the navigator's last report was no path, else
    ``stuck``; ``oscillating`` when the robot drove at least `OSCILLATION_TRAVEL` in the last
    `OSCILLATION_WINDOW` seconds and ended within `OSCILLATION_NET` of where that window
    began; else ``timeout_moving``.

    Parameters
    ----------
    times : (N,) array_like of float
        Sample times [s], increasing.
    xy : (N, 2) array_like of float
        True base positions at those times [m].
    success : bool
        The benchmark's success.
    contacts : int
        Contact events.
    reported_goal, reported_no_path : bool
        The navigator's last status.

    Returns
    -------
    reason : str
        One of `END_REASONS`.

    """
    if success:
        return ''
    if contacts:
        return 'collision'
    if reported_goal:
        return 'false_arrival'
    times = np.asarray(times, dtype=np.float64)
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    if times.shape[0] < 2:
        return 'no_path' if reported_no_path else 'stuck'
    step = np.hypot(*np.diff(xy, axis=0).T)
    end = times[-1]
    recent = step[times[1:] > end - STUCK_WINDOW].sum()
    if recent < STUCK_DISTANCE:
        return 'no_path' if reported_no_path else 'stuck'
    window = times[1:] > end - OSCILLATION_WINDOW
    first = int(np.argmax(times >= end - OSCILLATION_WINDOW))
    if (step[window].sum() >= OSCILLATION_TRAVEL
            and math.dist(xy[first], xy[-1]) < OSCILLATION_NET):
        return 'oscillating'
    return 'timeout_moving'


class TrajectoryRecorder:
    """
    Collect an episode's true state, once per scan, for `metrics`.

    Parameters
    ----------
    agent_radius : float
        Radius of the moving agents' circles [m].

    """

    def __init__(self, agent_radius):
        self.agent_radius = float(agent_radius)
        self._times = []
        self._poses = []
        self._velocities = []
        self._agent_distance = []

    def record(self, time, pose, velocity, agent_xy):
        """
        Record the state at one scan.

        Parameters
        ----------
        time : float
            Simulated time [s].
        pose : (3,) array_like of float
            True base pose ``(x, y, yaw)`` [m, m, rad].
        velocity : (2,) array_like of float
            True ``(v, omega)`` [m/s, rad/s].
        agent_xy : (K, 2) array_like of float
            The moving agents' true positions [m].

        """
        self._times.append(float(time))
        self._poses.append(tuple(float(v) for v in pose[:3]))
        self._velocities.append(tuple(float(v) for v in velocity[:2]))
        agent_xy = np.asarray(agent_xy, dtype=np.float64).reshape(-1, 2)
        if agent_xy.shape[0]:
            distance = np.hypot(agent_xy[:, 0] - pose[0], agent_xy[:, 1] - pose[1]).min()
            self._agent_distance.append(float(distance) - self.agent_radius)
        else:
            self._agent_distance.append(math.inf)

    def metrics(self, goal, shortest_path, time_limit, path_length, contacts, reported_goal,
                reported_no_path):
        """
        Return the episode's `EpisodeMetrics` from what was recorded.

        Parameters
        ----------
        goal : (2,) array_like of float
            The goal [m].
        shortest_path : float
            The reference shortest path ``L`` [m].
        time_limit : float
            [s]
        path_length : float
            Distance driven [m].
        contacts : int
            Contact events.
        reported_goal, reported_no_path : bool
            The navigator's status at the end.

        Returns
        -------
        EpisodeMetrics

        """
        if not self._times:
            raise ValueError('no state recorded')
        times = np.array(self._times)
        poses = np.array(self._poses)
        velocities = np.array(self._velocities)
        end = times[-1]
        goal_distance = math.dist(poses[-1, :2], goal[:2])
        success = bool(goal_distance <= GOAL_TOLERANCE and end < time_limit and not contacts)
        reference_time = shortest_path / REFERENCE_SPEED
        ok = success and math.isfinite(shortest_path) and shortest_path > 0.0
        dt = np.diff(times)
        distance = np.array(self._agent_distance)
        finite = np.isfinite(distance)
        inside = (distance[:-1] < PERSONAL_SPACE) & finite[:-1]
        still = ((np.abs(velocities[:-1, 0]) < STILL_LINEAR)
                 & (np.abs(velocities[:-1, 1]) < STILL_ANGULAR))
        return EpisodeMetrics(
            goal_distance=goal_distance, judged_success=success,
            end_reason=end_reason(times, poses[:, :2], success, contacts, reported_goal,
                                  reported_no_path),
            spl=spl(success, shortest_path, path_length),
            barn_score=barn_score(success, shortest_path, end),
            time_ratio=end / reference_time if ok else None,
            path_ratio=path_length / shortest_path if ok else None,
            min_agent_distance=float(distance[finite].min()) if finite.any() else None,
            personal_space_time=float(dt[inside].sum()),
            jerk_rms=_jerk_rms(times, velocities[:, 0]),
            angular_jerk_rms=_jerk_rms(times, velocities[:, 1]),
            still_time=float(dt[still].sum()))


def _jerk_rms(times, velocity):
    """Return the RMS of the second derivative of a velocity sampled at ``times`` (0 if < 3)."""
    if times.shape[0] < 3:
        return 0.0
    acceleration = np.diff(velocity) / np.diff(times)
    jerk = np.diff(acceleration) / np.diff(times)[1:]
    return float(np.sqrt(np.mean(jerk * jerk)))
