"""
Freshness of sensor streams, judged on two clocks: the node's clock and the steady wall clock.

With ``use_sim_time`` the node's clock is ``/clock``: when the simulator dies, that clock stops
and a watchdog on it alone never fires. A stream here is stale when its last message is older
than the timeout on *either* clock, when it never came, or when the node's clock went back
past it (a simulator restart). Plain floats in, no ROS: the node feeds it times.

"""

import math


class SensorWatchdog:
    """
    Tell whether every sensor stream is fresh, on the node's clock and on the steady clock.

    Parameters
    ----------
    timeout : float
        A stream is stale when its last message is older than this on either clock [s];
        positive.
    streams : sequence of str
        Names of the watched streams, e.g. ``('scan', 'odometry')``.

    """

    def __init__(self, timeout, streams):
        timeout = float(timeout)
        if not (math.isfinite(timeout) and timeout > 0.0):
            raise ValueError(f'timeout must be positive and finite, got {timeout!r} s')
        if not streams:
            raise ValueError('watch at least one stream')
        self.timeout = timeout
        self._last = {name: None for name in streams}

    def heard(self, stream, clock_time, steady_time):
        """
        Record a message of ``stream``.

        Parameters
        ----------
        stream : str
            One of the watched streams.
        clock_time : float
            The node clock's time at arrival (simulated time with ``use_sim_time``) [s].
        steady_time : float
            The steady (monotonic wall) clock's time at arrival [s].

        """
        if stream not in self._last:
            raise KeyError(f'unknown stream {stream!r}; watched: {sorted(self._last)}')
        self._last[stream] = (float(clock_time), float(steady_time))

    def stale_streams(self, clock_time, steady_time):
        """
        Name the streams that are stale now.

        Parameters
        ----------
        clock_time, steady_time : float
            Now, on the node's clock and on the steady clock [s].

        Returns
        -------
        list of str
            The stale streams, in the order they were given; empty when all are fresh.

        """
        stale = []
        for name, last in self._last.items():
            if last is None:
                stale.append(name)
                continue
            clock_age = clock_time - last[0]
            steady_age = steady_time - last[1]
            if clock_age < 0.0 or clock_age > self.timeout or steady_age > self.timeout:
                stale.append(name)
        return stale

    def is_stale(self, clock_time, steady_time):
        """Tell whether any stream is stale now (see ``stale_streams``)."""
        return bool(self.stale_streams(clock_time, steady_time))


def steady_arrival_time(steady_now, system_now_ns, received_ns):
    """
    Steady-clock time at which a message reached this host.

    rmw stamps each message on arrival with the system clock (``MessageInfo``'s
    ``received_timestamp``). A node that is busy takes queued messages late; dating them by
    their arrival rather than by the callback keeps a backlog from looking fresh.

    Parameters
    ----------
    steady_now : float
        The steady clock now [s].
    system_now_ns : int
        The system clock now [ns].
    received_ns : int or None
        The message's arrival on the system clock [ns]; None or 0 when unknown.

    Returns
    -------
    float
        ``steady_now`` less the message's age, the age clipped to ``[0, 60]`` s against system
        clock steps [s].

    """
    if not received_ns:
        return steady_now
    age = min(max((system_now_ns - received_ns) * 1e-9, 0.0), 60.0)
    return steady_now - age
