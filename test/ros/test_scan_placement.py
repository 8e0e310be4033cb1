"""
`ScanPlacer` under ``pose_source: auto``: TF takes over from odometry, and says so once.

A node started a moment before the node that publishes the laser's mount on ``/tf_static``
places its first scans from odometry with the ``laser_*`` mount (a CI run mapped an upside-down
laser's first scans mirrored that way and never reached its goal); the node drops that map
when `ScanPlacer.take_tf_takeover` says TF took over.
"""

from dpn_navigator.core.pose_history import PoseHistory
from dpn_navigator.ros.scan_placement import PoseNotYet, ScanNotPlaced, ScanPlacer
from dpn_navigator.ros.tf_pose_source import TransformUnavailable
import numpy as np
import pytest

SECOND = 1_000_000_000
LASER_IN_MAP = (np.eye(3), np.array([1.0, 2.0, 0.3]))   # (rotation, translation [m])


class LateTf:
    """A TF buffer that links ``map`` to every frame once ``arrive`` is called."""

    kind = 'test'

    def __init__(self):
        self.linked = False

    def arrive(self):
        self.linked = True

    def connected(self, target, source):
        return self.linked

    def sample_step(self, frame, stamp_ns):
        return 0.02, 0.01, 0.01                # 50 Hz transforms of a moving robot

    def lookup(self, target, source, stamp_ns):
        if not self.linked:
            raise TransformUnavailable(f'no {target} -> {source}')
        return LASER_IN_MAP


def placer(mode='auto', auto_wait=0.0):
    """Return ``(placer, tf, sources announced)``; odometry at 10 Hz over 5 s."""
    history = PoseHistory(span=6.0)
    for step in range(51):
        history.add(step * 0.1, (0.5, 0.5, 0.0))
    tf = LateTf()
    announced = []
    return (ScanPlacer(mode, 'map', 'base_link', tf, history, 0.05,
                       on_source=announced.append, auto_wait=auto_wait), tf, announced)


def scan_fields():
    return {'ranges': np.full(5, 3.0), 'angle_min': -0.2, 'angle_increment': 0.1,
            'angle_max': 0.2}


def test_tf_that_comes_late_takes_over_and_says_so_once():
    auto, tf, announced = placer()
    for stamp in (0.5, 0.9, 1.3):
        assert auto.place('laser', int(stamp * SECOND), scan_fields()).source == 'odom'
    assert auto.placed_from_odometry == 3 and not auto.take_tf_takeover()
    tf.arrive()
    placement = auto.place('laser', int(1.4 * SECOND), scan_fields())
    assert placement.source == 'tf' and announced == ['odom', 'tf']
    assert placement.laser_pose[:2] == pytest.approx((1.0, 2.0))
    assert auto.take_tf_takeover() and not auto.take_tf_takeover()
    assert auto.place('laser', int(1.5 * SECOND), scan_fields()).source == 'tf'
    assert not auto.take_tf_takeover() and auto.placed_from_odometry == 3


def test_tf_from_the_first_scan_is_no_takeover():
    auto, tf, announced = placer()
    tf.arrive()
    assert auto.place('laser', int(0.5 * SECOND), scan_fields()).source == 'tf'
    assert not auto.take_tf_takeover() and announced == ['tf']


def test_odometry_mode_never_takes_tf():
    odom, tf, announced = placer('odom')
    tf.arrive()
    assert odom.place('laser', int(0.5 * SECOND), scan_fields()).source == 'odom'
    assert not odom.take_tf_takeover() and odom.placed_from_odometry == 0


def test_scans_of_the_wait_wait_for_tf():
    auto, tf, announced = placer(auto_wait=1.0)
    for stamp in (0.5, 0.9, 1.49):
        with pytest.raises(PoseNotYet, match='waiting 1 s for TF'):
            auto.place('laser', int(stamp * SECOND), scan_fields())
    tf.arrive()
    assert auto.place('laser', int(1.4 * SECOND), scan_fields()).source == 'tf'
    assert announced == ['tf'] and not auto.take_tf_takeover()


def test_without_tf_odometry_is_used_once_the_wait_is_over():
    auto, tf, announced = placer(auto_wait=1.0)
    with pytest.raises(PoseNotYet):
        auto.place('laser', int(0.5 * SECOND), scan_fields())
    assert auto.place('laser', int(1.5 * SECOND), scan_fields()).source == 'odom'
    assert announced == ['odom']
    with pytest.raises(ValueError, match='auto_wait'):
        ScanPlacer('auto', 'map', 'base_link', tf, PoseHistory(), 0.05, auto_wait=float('nan'))


class SteppedTf(LateTf):
    """A TF buffer whose base link's samples around every stamp are ``step`` apart."""

    def __init__(self, step):
        super().__init__()
        self.linked = True
        self.step = step

    def sample_step(self, frame, stamp_ns):
        assert frame == 'base_link'
        return self.step


@pytest.mark.parametrize('step, placed', [
    ((0.5, 0.0, 0.3), False),          # a long gap in which the robot turned
    ((0.5, 0.2, 0.0), False),          # ... or drove
    ((0.5, 0.005, 0.005), True),       # a long gap standing still
    ((0.1, 0.2, 0.3), True),           # a short step
    (None, True),                      # tf2_ros: the step is not known
])
def test_a_pose_interpolated_across_a_long_moving_gap_is_refused(step, placed):
    history = PoseHistory(span=6.0)
    tf = SteppedTf(step)
    placer = ScanPlacer('tf', 'map', 'base_link', tf, history, 0.05, max_gap=0.15)
    if placed:
        assert placer.place('laser', int(1.0 * SECOND), scan_fields()).source == 'tf'
    else:
        with pytest.raises(ScanNotPlaced, match='max_pose_gap 0.15 s'):
            placer.place('laser', int(1.0 * SECOND), scan_fields())
    assert placer.gap_skips == (0 if placed else 1)
    # No limit: always placed.
    unlimited = ScanPlacer('tf', 'map', 'base_link', tf, history, 0.05, max_gap=0.0)
    assert unlimited.place('laser', int(1.0 * SECOND), scan_fields()).source == 'tf'


def test_odometry_across_a_long_gap_in_a_turn_is_refused():
    history = PoseHistory(span=6.0)
    history.add(1.0, (0.0, 0.0, 0.0))
    history.add(1.1, (0.0, 0.0, 0.05))
    history.add(1.6, (0.0, 0.0, 0.6))          # five lost messages while turning
    odom = ScanPlacer('odom', 'map', 'base_link', None, history, 0.05, max_gap=0.15)
    assert odom.place('laser', int(1.05 * SECOND), scan_fields()).source == 'odom'
    with pytest.raises(ScanNotPlaced, match='turned 0.550 rad'):
        odom.place('laser', int(1.3 * SECOND), scan_fields())
    assert odom.gap_skips == 1
