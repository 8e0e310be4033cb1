"""Tests of the two-clock sensor watchdog and the command-topic monitor, without ROS."""

from dpn_navigator.ros.cmd_vel_monitor import CommandTopicMonitor
from dpn_navigator.ros.sensor_watchdog import SensorWatchdog, steady_arrival_time
import pytest


def fresh_watchdog():
    watchdog = SensorWatchdog(0.4, ('scan', 'odometry'))
    watchdog.heard('scan', 10.0, 100.0)
    watchdog.heard('odometry', 10.0, 100.0)
    return watchdog


def test_never_heard_streams_are_stale():
    watchdog = SensorWatchdog(0.4, ('scan', 'odometry'))
    assert watchdog.stale_streams(0.0, 0.0) == ['scan', 'odometry']
    watchdog.heard('odometry', 0.0, 0.0)
    assert watchdog.stale_streams(0.1, 0.1) == ['scan']


@pytest.mark.parametrize('clock_time, steady_time, stale', [
    (10.3, 100.3, []),
    (10.41, 100.1, ['scan', 'odometry']),       # the node clock ran on
    (10.0, 100.41, ['scan', 'odometry']),       # /clock stopped: the steady clock still runs
    (9.0, 100.1, ['scan', 'odometry']),         # time went backwards
])
def test_stale_on_either_clock(clock_time, steady_time, stale):
    assert fresh_watchdog().stale_streams(clock_time, steady_time) == stale


def test_one_stream_stale():
    watchdog = fresh_watchdog()
    watchdog.heard('scan', 10.3, 100.3)
    assert watchdog.stale_streams(10.5, 100.5) == ['odometry']
    assert watchdog.is_stale(10.5, 100.5)


@pytest.mark.parametrize('timeout', [0.0, -1.0, float('nan'), float('inf')])
def test_bad_timeout_raises(timeout):
    with pytest.raises(ValueError, match='timeout must be positive'):
        SensorWatchdog(timeout, ('scan',))


def test_no_streams_or_unknown_stream_raise():
    with pytest.raises(ValueError, match='at least one stream'):
        SensorWatchdog(0.4, ())
    with pytest.raises(KeyError, match='unknown stream'):
        SensorWatchdog(0.4, ('scan',)).heard('imu', 0.0, 0.0)


def test_command_topic_monitor_counts_conflicts():
    monitor = CommandTopicMonitor()
    assert not monitor.check(1)
    assert monitor.check(2) and (monitor.others, monitor.conflicts) == (1, 1)
    assert monitor.check(3) and (monitor.others, monitor.conflicts) == (2, 1)
    assert not monitor.check(1) and monitor.others == 0
    assert monitor.check(2) and monitor.conflicts == 2
    assert not monitor.check(0) and monitor.others == 0


@pytest.mark.parametrize('system_now_ns, received_ns, arrival', [
    (5_000_000_000, 4_700_000_000, 99.7),       # arrived 0.3 s ago
    (5_000_000_000, None, 100.0),               # unknown: now
    (5_000_000_000, 0, 100.0),
    (5_000_000_000, 6_000_000_000, 100.0),      # the system clock stepped back: age 0
    (500_000_000_000, 1, 40.0),                 # stepped forward: age clipped to 60 s
])
def test_steady_arrival_time(system_now_ns, received_ns, arrival):
    assert steady_arrival_time(100.0, system_now_ns, received_ns) == pytest.approx(arrival)
