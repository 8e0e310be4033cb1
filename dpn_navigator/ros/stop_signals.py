"""
SIGINT and SIGTERM taken from a node process's first moment: a flag, or an early way out.

Light on purpose (the standard library only): the nodes' console scripts install these handlers
before they import anything slow (rclpy, numpy, the numba kernels), so that a stop signal at
any moment of the start-up ends the process cleanly, with exit code 0 and no traceback
(``node_entry``). While the process is starting, a stop signal raises `StartupInterrupted`
out of whatever runs (an import, ``rclpy.init``, the node's constructor and warm-up), which
``spin.run_node`` and ``node_entry`` catch; once the node spins, it only sets the flag that the
spin loop reads between callbacks. Every later stop signal is ignored.

A handler's exception can surface where Python cannot propagate it: in a ``__del__`` or in a C
library's callback into Python (numba's LLVM object cache, while the kernels load). Python then
prints "Exception ignored in ..." with a traceback and goes on. While starting, a
``sys.unraisablehook`` drops exactly those `StartupInterrupted` reports (any other goes to the
previous hook); the flag stays set, so the start-up ends at its next check and the process
stops cleanly all the same.

"""

import signal
import sys

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class StartupInterrupted(BaseException):
    """
    A stop signal came while the process was starting: stop without a traceback.

    A ``BaseException``, like ``KeyboardInterrupt``, so that no ``except Exception`` of a
    library on the way swallows it.

    """


class StopRequest:
    """
    A flag set by SIGINT and SIGTERM, whose handlers this installs.

    Parameters
    ----------
    starting : bool
        Raise `StartupInterrupted` at the first stop signal until `started` is called.

    Attributes
    ----------
    signal_name : str or None
        The first signal received, e.g. ``'SIGTERM'``.

    """

    def __init__(self, starting=False):
        self.signal_name = None
        self.starting = starting
        self.unraisable_dropped = 0
        self._previous_unraisablehook = sys.unraisablehook
        if starting:
            sys.unraisablehook = self._on_unraisable
        for signum in STOP_SIGNALS:
            signal.signal(signum, self._on_signal)

    def _on_unraisable(self, report):
        """Drop the report of a `StartupInterrupted` raised where it could not propagate."""
        if isinstance(report.exc_value, StartupInterrupted):
            self.unraisable_dropped += 1
            return
        self._previous_unraisablehook(report)

    def _on_signal(self, signum, frame):
        if self.signal_name is None:
            self.signal_name = signal.Signals(signum).name
        # Later stop signals are ignored, not handled: at exit Python puts the default action
        # back for signals with a Python handler (not for ignored ones), and a second Ctrl-C
        # arriving then would kill the stopping process (exit -2) instead of letting it end.
        for stop_signal in STOP_SIGNALS:
            signal.signal(stop_signal, signal.SIG_IGN)
        if self.starting:
            self.starting = False
            raise StartupInterrupted(self.signal_name)

    def started(self):
        """Leave the start-up: from now on a stop signal only sets the flag."""
        self.starting = False
        if sys.unraisablehook == self._on_unraisable:
            sys.unraisablehook = self._previous_unraisablehook

    @property
    def requested(self):
        """Tell whether a stop signal came."""
        return self.signal_name is not None
