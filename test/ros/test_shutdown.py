"""
SIGINT and SIGTERM end both node processes cleanly, busy or not: exit code 0, no traceback.

Ten world + navigator pairs (five at a time, all in this test's domain, so every navigator
hears scans and every world commands) run for a moment; then each process gets SIGINT or
SIGTERM, once or twice in a row as an impatient Ctrl-C does: ten processes each signal.
"""

import os
from pathlib import Path
import signal
import subprocess
import time

from dpn_navigator.tools.demo import installed_executable, ros_environment, start_nodes, stop_nodes
import pytest

PAIRS_PER_BATCH = 5
BATCHES = 2
READY = {'dpn': 'dpn ready', 'pybullet_world': 'real-time factor'}
BUSY_TIME = 1.5             # [s] of callbacks after both nodes are ready
EXIT_TIMEOUT = 10.0         # [s]


def wait_ready(pairs, timeout=60.0):
    deadline = time.monotonic() + timeout
    logs = [(Path(log_dir) / f'{name}.log', marker) for log_dir, _ in pairs
            for name, marker in READY.items()]
    while time.monotonic() < deadline:
        if all(path.exists() and marker in path.read_text() for path, marker in logs):
            return
        time.sleep(0.1)
    raise AssertionError(f'nodes not ready after {timeout} s: '
                         + '; '.join(path.read_text()[-500:] for path, _ in logs))


@pytest.mark.slow
def test_sigint_and_sigterm_end_busy_nodes_cleanly(ros_domain_id, tmp_path):
    outcomes = []
    for batch in range(BATCHES):
        pairs = []
        try:
            for index in range(PAIRS_PER_BATCH):
                log_dir = tmp_path / f'batch{batch}_pair{index}'
                _, processes = start_nodes('back_and_forth', 0, 3, index, 2.0, ros_domain_id,
                                           log_dir)
                pairs.append((log_dir, processes))
            wait_ready(pairs)
            time.sleep(BUSY_TIME)
            signalled = []
            for index, (log_dir, processes) in enumerate(pairs):
                first = signal.SIGINT if index % 2 == 0 else signal.SIGTERM
                second = signal.SIGTERM if first == signal.SIGINT else signal.SIGINT
                for name, signum in (('dpn', first), ('pybullet_world', second)):
                    process = processes[name]
                    os.killpg(process.pid, signum)         # as launch signals a group
                    if batch == 1:
                        time.sleep(0.02)
                        os.killpg(process.pid, signum)     # Ctrl-C pressed twice
                    signalled.append((log_dir / f'{name}.log', signum, process))
            for log, signum, process in signalled:
                code = process.wait(EXIT_TIMEOUT)
                outcomes.append((signum, code, log.read_text()))
        finally:
            for _, processes in pairs:
                stop_nodes(processes)
    assert len(outcomes) == 2 * BATCHES * PAIRS_PER_BATCH
    for signum in (signal.SIGINT, signal.SIGTERM):
        assert sum(1 for s, _, _ in outcomes if s == signum) >= 10
    for signum, code, text in outcomes:
        assert code == 0, (signum, code, text[-2000:])
        assert 'Traceback' not in text and 'Error' not in text, (signum, text[-2000:])
        assert f'{signal.Signals(signum).name}: stopping' in text, text[-2000:]


def test_absurd_grid_parameters_end_in_one_error_line(ros_domain_id):
    command = [str(installed_executable('dpn_navigator', 'dpn')), '--ros-args',
               '-p', 'map_width:=1000000.0', '-p', 'resolution:=0.01']
    result = subprocess.run(command, env=ros_environment(ros_domain_id), capture_output=True,
                            text=True, timeout=60)
    output = result.stdout + result.stderr
    assert result.returncode == 1, output
    assert 'cannot start' in output and 'use a coarser resolution' in output, output
    assert 'Traceback' not in output and 'MemoryError' not in output, output


@pytest.fixture
def stop_handlers_restored():
    """Put back the process's SIGINT and SIGTERM handlers after a test that installs its own."""
    saved = {signum: signal.getsignal(signum) for signum in (signal.SIGINT, signal.SIGTERM)}
    yield
    for signum, handler in saved.items():
        signal.signal(signum, handler)


@pytest.mark.usefixtures('stop_handlers_restored')
def test_a_stop_signal_is_taken_once_and_later_ones_are_ignored():
    from dpn_navigator.ros.spin import StopRequest
    stop = StopRequest()
    assert not stop.requested
    os.kill(os.getpid(), signal.SIGTERM)
    assert stop.signal_name == 'SIGTERM'
    # Ignored, not handled by Python: Python's exit puts back the default action (which
    # kills) only for signals with a Python handler.
    assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_IGN
    os.kill(os.getpid(), signal.SIGINT)
    assert stop.signal_name == 'SIGTERM'


#: Moments after the start [s] at which a stop signal is sent: the imports (rclpy, numpy,
#: numba), the kernels' warm-up and the first callbacks.
EARLY_DELAYS = (0.2, 0.5, 1.0, 2.0)


@pytest.mark.slow
@pytest.mark.parametrize('package, name', [('dpn_navigator', 'dpn'),
                                           ('sim_bridge', 'pybullet_world')])
def test_a_stop_signal_during_start_up_ends_the_process_cleanly(ros_domain_id, tmp_path,
                                                                package, name):
    executable = str(installed_executable(package, name))
    outcomes = []
    for delay in EARLY_DELAYS:
        for signum in (signal.SIGINT, signal.SIGTERM):
            log_path = tmp_path / f'{name}_{signum.name}_{delay}.log'
            with open(log_path, 'w') as log:
                process = subprocess.Popen([executable], env=ros_environment(ros_domain_id),
                                           stdout=log, stderr=subprocess.STDOUT,
                                           start_new_session=True)
            try:
                time.sleep(delay)
                os.kill(process.pid, signum)
                code = process.wait(EXIT_TIMEOUT)
            finally:
                if process.poll() is None:
                    stop_nodes({name: process})
            outcomes.append((signum.name, delay, code, log_path.read_text()))
    for signum, delay, code, text in outcomes:
        assert code == 0, (signum, delay, code, text[-2000:])
        assert 'Traceback' not in text, (signum, delay, text[-2000:])
        assert f'{signum}' in text and 'stopping' in text, (signum, delay, text[-2000:])


class SignalledInDel:
    """An object whose ``__del__`` receives the stop signal: Python cannot raise from there."""

    def __del__(self):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.2)                     # the handler runs here, inside __del__


def wait_for(condition, timeout=2.0):
    deadline = time.monotonic() + timeout
    while not condition() and time.monotonic() < deadline:
        time.sleep(0.01)                    # Python handlers run between bytecodes


@pytest.mark.usefixtures('stop_handlers_restored')
def test_a_stop_signal_while_starting_ends_the_process_at_once_with_one_line(capfd):
    from dpn_navigator.ros.stop_signals import StopRequest
    exits = []
    stop = StopRequest(starting=True, name='dpn', exit_process=exits.append)
    os.kill(os.getpid(), signal.SIGINT)
    wait_for(lambda: exits)
    assert exits == [0]
    assert capfd.readouterr().err == 'dpn: SIGINT during start-up: stopping\n'
    assert stop.requested and not stop.starting
    os.kill(os.getpid(), signal.SIGTERM)                # ignored from now on
    time.sleep(0.1)
    assert exits == [0] and stop.signal_name == 'SIGINT'
    stop = StopRequest(starting=True, name='dpn', exit_process=exits.append)
    stop.started()
    os.kill(os.getpid(), signal.SIGTERM)                # a flag only, once started
    wait_for(lambda: stop.requested)
    assert stop.signal_name == 'SIGTERM' and exits == [0]
    assert capfd.readouterr().err == ''


@pytest.mark.usefixtures('stop_handlers_restored')
def test_the_start_up_stop_line_reaches_stderr_while_a_library_silences_it(capfd):
    # The world silences pybullet's URDF warnings by pointing fd 2 at /dev/null while it loads
    # the bodies (sim_bridge.scene); a stop signal landing then still says why it stops.
    from dpn_navigator.ros.stop_signals import StopRequest
    from sim_bridge.scene import _quiet_native_output
    exits = []
    stop = StopRequest(starting=True, name='pybullet_world', exit_process=exits.append)
    with _quiet_native_output():
        os.write(2, b'silenced\n')
        os.kill(os.getpid(), signal.SIGTERM)
        wait_for(lambda: exits)
    assert exits == [0]
    err = capfd.readouterr().err        # importing pybullet prints its build time first
    assert err.endswith('pybullet_world: SIGTERM during start-up: stopping\n'), err
    assert 'silenced' not in err
    stop.started()


@pytest.mark.usefixtures('stop_handlers_restored')
def test_a_stop_signal_where_python_cannot_raise_ends_the_start_up_all_the_same(capfd):
    # As in numba's LLVM object cache callback while the kernels load: an exception raised by
    # the handler there was only printed ("Exception ignored ..."); an exit is not lost.
    from dpn_navigator.ros.stop_signals import StopRequest
    exits = []
    StopRequest(starting=True, name='pybullet_world', exit_process=exits.append)
    SignalledInDel()                    # dropped at once: __del__ runs here
    assert exits == [0]
    err = capfd.readouterr().err
    assert err == 'pybullet_world: SIGTERM during start-up: stopping\n', err
