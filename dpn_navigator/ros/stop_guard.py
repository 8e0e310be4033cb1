"""
The stop on stale sensors, beside the executor: a steady-clock thread, and commands gated.

The ``dpn`` node's callbacks run one at a time on its executor; a scan callback that plans for
a second (a search that finds no path on a large map, a turn-place search) would hold back a
watchdog timer on the same executor, and a world killed then was stopped a second late. Here a
thread of its own looks at the `SensorWatchdog` every ``period`` of the steady clock, in every
state of the navigator (driving, standing, idle, no path), and sends a zero command while a
stream is stale. Every other command goes through `StopGuard.publish`, which sends it only
while the sensors are fresh, under the same lock as the thread's check: once the stop has been
sent, no command follows it until a fresh scan and odometry arrive.

"""

import threading


class StopGuard:
    """
    Zero commands while a sensor stream is stale; other commands only while all are fresh.

    Parameters
    ----------
    watchdog : SensorWatchdog
        The streams' freshness; fed through `heard` only, from now on.
    command_publisher : CommandPublisher
        Where commands go (``publish(linear, angular)``).
    clock_seconds, steady_seconds : callable() -> float
        Now on the node's clock and on the steady clock [s]; called from both threads.
    period : float
        Time between two checks of the thread, on the steady clock [s].
    on_error : callable(Exception), optional
        Told when a zero command could not be sent (e.g. the context was shut down); the
        thread then ends.

    """

    def __init__(self, watchdog, command_publisher, clock_seconds, steady_seconds, period,
                 on_error=None):
        self.watchdog = watchdog
        self.command_publisher = command_publisher
        self.clock_seconds = clock_seconds
        self.steady_seconds = steady_seconds
        self.period = float(period)
        self.on_error = on_error
        self.stops_sent = 0
        #: Whether commands go out at all: false while the (lifecycle) node is not active, so
        #: that an inactive navigator sends nothing, not even zeros, to another controller's
        #: robot.
        self.enabled = True
        self._lock = threading.Lock()
        self._closing = threading.Event()
        self._thread = None

    def start(self):
        """Start the checking thread (a daemon)."""
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name='dpn_stop_guard',
                                            daemon=True)
            self._thread.start()

    @property
    def running(self):
        """Tell whether the checking thread runs."""
        return self._thread is not None and self._thread.is_alive()

    def heard(self, stream, clock_time, steady_time):
        """Record a message of ``stream`` (``SensorWatchdog.heard``)."""
        with self._lock:
            self.watchdog.heard(stream, clock_time, steady_time)

    def stale_streams(self):
        """Name the streams stale now (``SensorWatchdog.stale_streams``)."""
        with self._lock:
            return self.watchdog.stale_streams(self.clock_seconds(), self.steady_seconds())

    def publish(self, linear, angular):
        """
        Send a command if every stream is fresh now; return whether it was sent.

        Parameters
        ----------
        linear, angular : float
            [m/s, rad/s]

        """
        with self._lock:
            if not self.enabled or self.watchdog.is_stale(self.clock_seconds(),
                                                          self.steady_seconds()):
                return False
            self.command_publisher.publish(linear, angular)
            return True

    def check(self):
        """Send a zero command if a stream is stale now; return the stale streams."""
        with self._lock:
            stale = self.watchdog.stale_streams(self.clock_seconds(), self.steady_seconds())
            if stale and self.enabled:
                self.command_publisher.publish(0.0, 0.0)
                self.stops_sent += 1
            return stale

    def close(self, timeout=1.0):
        """Stop the thread and wait for it, at most ``timeout`` [s]."""
        self._closing.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout)

    def _run(self):
        while not self._closing.wait(self.period):
            try:
                self.check()
            except Exception as error:  # noqa: B902 (rclpy raises several kinds at shutdown)
                if not self._closing.is_set() and self.on_error is not None:
                    self.on_error(error)
                return
