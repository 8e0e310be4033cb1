"""
Acceleration limits on the velocity commands, as Nav2's velocity_smoother applies them.

The path follower turns a path into a command per scan; between two scans it may step from
standing to full speed, which a base without its own ramp turns into a jerk (or a wheel slip
that drifts the odometry). `AccelerationLimiter` lets the speed *grow* by at most ``max_accel *
dt`` per command, per axis; slowing down, stopping and reversing the sign pass at once (the
reversal through zero), since stopping is the safe side and the base's own controller limits
its deceleration. A limit of 0 turns the axis's limit off.

"""

import math


class AccelerationLimiter:
    """
    Limit the growth of linear and angular speed between successive commands.

    Parameters
    ----------
    max_linear_accel : float
        [m/s^2]; 0: no limit.
    max_angular_accel : float
        [rad/s^2]; 0: no limit.
    first_period : float
        The time step assumed before the first command, and the longest step counted [s].

    """

    def __init__(self, max_linear_accel, max_angular_accel, first_period=0.1):
        for name, value in (('max_linear_accel', max_linear_accel),
                            ('max_angular_accel', max_angular_accel),
                            ('first_period', first_period)):
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        self.limits = (float(max_linear_accel), float(max_angular_accel))
        self.first_period = float(first_period)
        self.last = (0.0, 0.0)
        self.last_stamp = None

    def reset(self, stamp=None):
        """Take the robot as standing still at ``stamp`` [s] (after a stop sent elsewhere)."""
        self.last = (0.0, 0.0)
        self.last_stamp = stamp

    def limit(self, linear, angular, stamp):
        """
        Return the command ``(linear, angular)`` with its speed growth limited.

        Parameters
        ----------
        linear, angular : float
            The wanted command [m/s, rad/s].
        stamp : float
            Its time [s], any monotonic clock; a step back in time counts as the first period.

        """
        if self.last_stamp is None or not stamp > self.last_stamp:
            dt = self.first_period
        else:
            dt = min(stamp - self.last_stamp, self.first_period * 10.0)
        out = []
        for wanted, previous, max_accel in zip((linear, angular), self.last, self.limits):
            if max_accel <= 0.0 or abs(wanted) <= abs(previous) and wanted * previous >= 0.0:
                out.append(float(wanted))           # no limit, or slowing down
                continue
            start = previous if wanted * previous > 0.0 else 0.0
            step = max_accel * dt
            grown = min(abs(wanted), abs(start) + step)
            out.append(math.copysign(grown, wanted))
        self.last = (out[0], out[1])
        self.last_stamp = stamp
        return self.last
