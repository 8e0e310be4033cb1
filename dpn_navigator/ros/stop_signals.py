"""
SIGINT and SIGTERM taken from a node process's first moment: an early way out, then a flag.

Light on purpose (the standard library only): the nodes' console scripts install these handlers
before they import anything slow (rclpy, numpy, the numba kernels), so that a stop signal at
any moment of the start-up ends the process cleanly, with exit code 0, one line on stderr and
no traceback (``node_entry``). Once the node spins, a stop signal only sets the flag that the
spin loop reads between callbacks (``spin.run_node``). Every later stop signal is ignored.

While the process starts, a stop signal ends it at once (``os._exit``): nothing is left to
clean up before the node spins (no command sent, no file written), and nothing half-built is
finalised. An exception raised out of the handler instead, as here before, lands wherever the
start-up is: in the middle of a C extension's import (llvmlite's, numba's), in a ``__del__`` or
in numba's LLVM object-cache callback, where Python cannot propagate it. One CI run out of
about twenty then saw the ``dpn`` process end with a segfault (exit -11, empty log) when the
signal came 1.0 s into the start-up, during those imports.

"""

import os
import signal

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def exit_at_once(code):
    """End the process now with ``code``, without finalising anything (``os._exit``)."""
    os._exit(code)


def _duplicate(fd):
    """Return a duplicate of file descriptor ``fd``, or None when it is not open."""
    try:
        return os.dup(fd)
    except OSError:
        return None


class StopRequest:
    """
    A flag set by SIGINT and SIGTERM, whose handlers this installs.

    Parameters
    ----------
    starting : bool
        End the process at the first stop signal until `started` is called: write
        ``'<name>: <signal> during start-up: stopping'`` on stderr, then ``exit_process(0)``.
    name : str
        The process's name in that line, e.g. ``'dpn'``.
    exit_process : callable
        Called with the exit code to end a process stopped while starting; by default
        `exit_at_once`. Tests give a recorder.

    Attributes
    ----------
    signal_name : str or None
        The first signal received, e.g. ``'SIGTERM'``.

    """

    def __init__(self, starting=False, name='node', exit_process=exit_at_once):
        self.signal_name = None
        self.starting = starting
        self.name = name
        self._exit_process = exit_process
        # The line goes to the stderr the process started with, even while a library has
        # pointed fd 2 elsewhere (the world silences pybullet's URDF warnings that way).
        self._stderr = _duplicate(2) if starting else None
        for signum in STOP_SIGNALS:
            signal.signal(signum, self._on_signal)

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
            line = f'{self.name}: {self.signal_name} during start-up: stopping\n'
            try:
                os.write(2 if self._stderr is None else self._stderr, line.encode())
            except OSError:
                pass                        # no stderr: stop all the same
            self._exit_process(0)

    def started(self):
        """Leave the start-up: from now on a stop signal only sets the flag."""
        self.starting = False
        if self._stderr is not None:
            os.close(self._stderr)
            self._stderr = None

    @property
    def requested(self):
        """Tell whether a stop signal came."""
        return self.signal_name is not None
