"""
Fault test of the watchdog over DDS: when scans, odometry or ``/clock`` stop, the robot stops.

A probe drives the dpn node (on simulated time: the probe publishes ``/clock`` as the simulator
does) with a healthy stream in an open room, so that the node commands motion; then one stream
stops, or everything stops as when the simulator dies. The first zero command must follow the
last message within ``sensor_timeout`` plus one watchdog period (0.42 s by default) plus the
delivery, on the wall clock: under 0.5 s.
"""

import time

from dpn_navigator.ros.dpn_node import WATCHDOG_PERIOD
from node_harness import executor_for, spin_until
import pytest
from sim_stand_in import room_navigator, SimulatorStandIn

STOP_LIMIT = 0.5            # [s] of wall time, last message to first zero command
TRIALS = 3


def run_for(executor, probe, seconds, streams):
    """Tick at 50 Hz for ``seconds`` of wall time; return the wall time of the last tick."""
    last = None
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        last = probe.tick(streams)
        spin_until(executor, lambda: False, timeout=0.02)
    return last


@pytest.fixture
def nodes(ros_context):
    dpn = room_navigator(ros_context)
    probe = SimulatorStandIn(ros_context)
    with executor_for(ros_context, dpn, probe) as executor:
        assert spin_until(executor, lambda: probe.scan_pub.get_subscription_count() > 0
                          and probe.clock_pub.get_subscription_count() > 0)
        yield dpn, probe, executor


def test_watchdog_period_leaves_room_in_the_default_timeout():
    assert 0.4 + WATCHDOG_PERIOD <= STOP_LIMIT - 0.05


@pytest.mark.parametrize('still_running', [
    ('clock', 'odometry'),          # scans stop
    ('clock', 'scan'),              # odometry stops
    ('clock',),                     # both stop, simulated time runs on
    (),                             # the simulator dies: /clock stops too
])
@pytest.mark.slow
def test_first_zero_command_follows_the_last_message_within_half_a_second(nodes, still_running):
    dpn, probe, executor = nodes
    all_streams = ('clock', 'odometry', 'scan')
    for _ in range(TRIALS):
        run_for(executor, probe, 1.0, all_streams)
        assert any(linear > 0.0 for _, linear, _ in probe.commands[-10:]), \
            'healthy streams in an open room: the robot should drive'
        assert not dpn.stale
        last_message = time.monotonic()
        probe.commands.clear()
        run_for(executor, probe, 1.0, still_running)
        zeros = [t for t, linear, angular in probe.commands if linear == angular == 0.0]
        assert zeros, probe.commands
        assert zeros[0] - last_message < STOP_LIMIT
        moving_after = [t for t, linear, angular in probe.commands
                        if (linear, angular) != (0.0, 0.0) and t > zeros[0]]
        assert not moving_after
        assert dpn.stale
        assert spin_until(executor, lambda: dpn.last_status is not None and dpn.stale)
