"""The benchmark's own view of an episode: outcome, failure reasons and standard measures."""

import math

from dpn_navigator.benchmark import episode_metrics as em
import numpy as np
import pytest


def straight(speed, duration, rate=10.0, start=(0.0, 0.0)):
    """Return the times and positions of a robot driving along +x at ``speed``."""
    times = np.arange(0.0, duration + 1e-9, 1.0 / rate)
    xy = np.column_stack((start[0] + speed * times, np.full(times.shape, start[1])))
    return times, xy


def test_time_limit_is_the_same_for_every_navigator():
    # 30 s + 3 L / 1 m/s, whatever speed a navigator declares (there is no such argument).
    assert em.time_limit(10.0) == pytest.approx(60.0)
    assert em.REFERENCE_SPEED == 1.0


def test_spl_and_barn_score_follow_their_formulas():
    assert em.spl(True, 10.0, 12.5) == pytest.approx(0.8)
    assert em.spl(True, 10.0, 9.0) == pytest.approx(1.0)       # a shorter path caps at 1
    assert em.spl(False, 10.0, 10.0) == 0.0
    assert em.spl(True, math.inf, 10.0) == 0.0
    # BARN: OT / clip(AT, 2 OT, 8 OT) with OT = L / v_ref.
    assert em.barn_score(True, 10.0, 15.0) == pytest.approx(0.5)
    assert em.barn_score(True, 10.0, 40.0) == pytest.approx(0.25)
    assert em.barn_score(True, 10.0, 200.0) == pytest.approx(1.0 / 8.0)
    assert em.barn_score(False, 10.0, 15.0) == 0.0


@pytest.mark.parametrize('speed, no_path, reason', [
    (0.0, True, 'no_path'), (0.0, False, 'stuck'), (0.02, False, 'stuck'),
    (0.5, False, 'timeout_moving')])
def test_end_reasons_from_the_motion(speed, no_path, reason):
    times, xy = straight(speed, 40.0)
    assert em.end_reason(times, xy, False, 0, False, no_path) == reason


def test_back_and_forth_is_oscillating():
    times = np.arange(0.0, 40.0, 0.1)
    # 1 m amplitude, period 5 s (1.3 m/s mean): after 30 s it is back where it was.
    xy = np.column_stack((np.sin(2.0 * np.pi * times / 5.0), np.zeros_like(times)))
    assert em.end_reason(times, xy, False, 0, False, False) == 'oscillating'


def test_contact_and_false_arrival_come_first():
    times, xy = straight(0.5, 20.0)
    assert em.end_reason(times, xy, False, 1, True, True) == 'collision'
    assert em.end_reason(times, xy, False, 0, True, False) == 'false_arrival'
    assert em.end_reason(times, xy, True, 0, False, False) == ''


def recorded(speed=1.0, duration=10.0, agents=None):
    recorder = em.TrajectoryRecorder(agent_radius=0.3)
    times, xy = straight(speed, duration)
    for t, (x, y) in zip(times, xy):
        recorder.record(t, (x, y, 0.0), (speed, 0.0), agents if agents is not None else
                        np.zeros((0, 2)))
    return recorder, xy[-1]


def test_success_is_judged_on_the_true_pose():
    recorder, end = recorded()
    close = recorder.metrics((end[0] + 0.25, end[1]), 10.0, 60.0, 10.0, 0, False, False)
    assert close.judged_success and close.end_reason == '' and close.spl == pytest.approx(1.0)
    assert close.time_ratio == pytest.approx(1.0) and close.path_ratio == pytest.approx(1.0)
    # The navigator's report does not matter: 0.35 m off is a failure even if it said arrived.
    far = recorder.metrics((end[0] + 0.35, end[1]), 10.0, 60.0, 10.0, 0, True, False)
    assert not far.judged_success and far.end_reason == 'false_arrival' and far.spl == 0.0
    assert far.time_ratio is None
    touched = recorder.metrics(tuple(end), 10.0, 60.0, 10.0, 1, True, False)
    assert not touched.judged_success and touched.end_reason == 'collision'


def test_agent_clearance_personal_space_jerk_and_still_time():
    # An agent at (5, 1): the robot passes 1 m from its centre, 0.7 m from its edge.
    recorder, end = recorded(agents=np.array([[5.0, 1.0]]))
    metrics = recorder.metrics(tuple(end), 10.0, 60.0, 10.0, 0, True, False)
    assert metrics.min_agent_distance == pytest.approx(0.7)
    # Edge within 1.2 m: centre within 1.5 m, |x - 5| < sqrt(1.5^2 - 1) = 1.118 m at 1 m/s.
    assert metrics.personal_space_time == pytest.approx(2.2, abs=0.11)
    assert metrics.jerk_rms == 0.0 and metrics.still_time == 0.0
    standing, end = recorded(speed=0.0)
    metrics = standing.metrics((5.0, 0.0), 10.0, 60.0, 0.0, 0, False, False)
    assert metrics.still_time == pytest.approx(10.0) and metrics.min_agent_distance is None
    assert metrics.end_reason == 'stuck'
    jerky = em.TrajectoryRecorder(0.3)
    for k, v in enumerate([0.0, 0.0, 1.0, 0.0, 0.0]):
        jerky.record(0.1 * k, (0.0, 0.0, 0.0), (v, 0.0), np.zeros((0, 2)))
    # Accelerations 0, 10, -10, 0 m/s^2; jerks 100, -200, 100 m/s^3.
    assert jerky.metrics((0.0, 0.0), 1.0, 60.0, 0.0, 0, True, False).jerk_rms == \
        pytest.approx(math.sqrt((100 ** 2 + 200 ** 2 + 100 ** 2) / 3))


def test_metrics_need_a_recorded_state():
    with pytest.raises(ValueError, match='no state'):
        em.TrajectoryRecorder(0.3).metrics((0.0, 0.0), 1.0, 60.0, 0.0, 0, False, False)
