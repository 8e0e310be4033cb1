"""
The foresight oracle's view of the moving agents: where each will be over a short horizon.

The bare oracle blocks every agent's inflated footprint anywhere on the map at every step, so
an agent standing in a corridor far ahead closes the only route although it will have moved on
long before the robot gets there (180 of its 2,244 episodes ended with no path). The foresight
oracle blocks instead, for the agents that can meet the robot within `HORIZON` seconds (within
`interest_radius` of it), their positions **predicted with constant velocity** over that horizon
(the true velocity, from two consecutive true positions): the robot plans around where they are
going, and with no way past waits for them (the navigator's no-path retry); an agent farther
away is ignored until it is near. It is a prediction, not the simulation's future: an agent
that stops (for the robot, or for another) or turns does not do so in the forecast, which the
next step corrects (docs/benchmark.md says where that leaves the oracle below another
navigator).

"""

import numpy as np

#: Forecast horizon [s] and its sampling step [s].
HORIZON = 2.0
HORIZON_STEP = 0.25
#: Closing speed that sets the radius of interest: the robot's reference speed plus the
#: fastest agent's (a pedestrian, 1.4 m/s) [m/s].
CLOSING_SPEED = 2.4


def interest_radius(reach, horizon=HORIZON, closing_speed=CLOSING_SPEED):
    """Return the distance [m] within which an agent can meet the robot within ``horizon``."""
    return reach + closing_speed * horizon


def forecast_positions(positions, previous, dt, robot_xy, reach, horizon=HORIZON,
                       step=HORIZON_STEP):
    """
    Return the predicted positions of the agents near the robot over the horizon.

    Parameters
    ----------
    positions : (K, 2) array_like of float
        The agents' true positions now [m].
    previous : (K, 2) array_like of float, or None
        Their positions one scan earlier [m]; None (or another shape): standing still.
    dt : float
        Time between the two [s], positive.
    robot_xy : (2,) array_like of float
        The robot's position [m].
    reach : float
        ``R + r`` [m]: how far an agent's blocked cells reach.
    horizon, step : float
        Forecast horizon and step [s].

    Returns
    -------
    points : (M, 2) ndarray of float64
        For every agent within `interest_radius` of the robot, its positions at ``0, step,
        ..., horizon`` seconds on, at its current velocity.

    """
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    if positions.shape[0] == 0:
        return np.zeros((0, 2))
    velocity = np.zeros_like(positions)
    if previous is not None and dt > 0.0:
        previous = np.asarray(previous, dtype=np.float64).reshape(-1, 2)
        if previous.shape == positions.shape:
            velocity = (positions - previous) / dt
    distance = np.hypot(positions[:, 0] - robot_xy[0], positions[:, 1] - robot_xy[1])
    near = distance <= interest_radius(reach, horizon)
    times = np.arange(0.0, horizon + 1e-9, step)
    points = positions[near, None, :] + velocity[near, None, :] * times[None, :, None]
    return points.reshape(-1, 2)
