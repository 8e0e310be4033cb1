"""What a recording's laser did (``recording.sensor_survey``), and the hints it gives."""

import math

from dpn_navigator.recording.sensor_survey import (NO_ECHO_HINT_SHARE, SensorSurvey,
                                                   STANDING_DISTANCE)
import numpy as np


def test_the_survey_counts_no_echo_codes_no_returns_and_travel():
    survey = SensorSurvey()
    survey.add([0.0, 0.019, 0.5, math.inf, math.nan, -math.inf, 30.0, 29.9], 0.02, 30.0,
               (1.0, 2.0))
    survey.add(np.array([0.01, 1.0], np.float32), 0.02, 30.0, (1.0, 2.5))
    assert survey.readings == 10 and survey.scans == 2
    assert survey.no_echo_codes == 3            # 0.0, 0.019, 0.01; not NaN, not -inf
    assert survey.no_returns == 2               # +inf and 30.0 (at range_max)
    assert survey.travel == 0.5 and not survey.standing
    assert survey.share(survey.no_echo_codes) == 0.3


def _survey(no_echo_share, no_return_share, travel, beams=1000, scans=5, lost_every=0):
    survey = SensorSurvey()
    for k in range(scans):
        ranges = np.full(beams, 3.0)
        ranges[:int(no_echo_share * beams)] = 0.0
        ranges[beams - int(no_return_share * beams):] = math.inf
        if lost_every:
            ranges[beams // 2:int((1.0 - no_return_share) * beams) - 1:lost_every] = math.nan
        survey.add(ranges, 0.02, 30.0, (travel * k / (scans - 1), 0.0))
    return survey


def test_lost_returns_are_lone_beams_without_a_hit_inside_a_surface():
    survey = SensorSurvey()
    # A surface at 3 m with one beam lost, then two, then a run of three; a jump from 3 to 5 m
    # with one beam lost between; a code below range_min between two hits.
    ranges = [3.0, math.inf, 3.05, math.nan, math.inf, 3.1, math.inf, math.inf, math.inf, 3.1,
              math.inf, 5.0, 0.01, 5.1]
    survey.add(ranges, 0.02, 30.0, (0.0, 0.0))
    assert survey.lost_returns == 1 + 2 + 1


def test_a_standing_laser_with_no_echo_codes_is_told_both_files_and_settings():
    hints = _survey(0.2, 0.0, 0.0).hints({})
    assert len(hints) == 2
    assert '20 %' in hints[0] and 'no_echo_below_range_min: true' in hints[0]
    assert 'config/dpn_standing_laser.yaml' in hints[1]
    # What the parameters given already cater for is not hinted at.
    assert _survey(0.2, 0.0, 0.0).hints({'no_echo_below_range_min': True,
                                         'free_burn_in': 5.0}) == []
    # Few codes, or the paper's rule set: no file, no code hint below the share.
    few = NO_ECHO_HINT_SHARE / 2.0
    assert _survey(few, 0.0, 0.0).hints({}, files=False) == []


def test_a_moving_laser_with_silent_beams_is_told_the_real_laser_file():
    survey = _survey(0.0, 0.4, 3.0, lost_every=50)
    assert survey.travel == 3.0 and not survey.standing
    assert survey.share(survey.lost_returns) == 0.002
    # By default the navigator takes the real-laser settings itself (real_laser_switch).
    assert survey.hints({}) == []
    off = {'real_laser_switch': 0.0}
    (hint,) = survey.hints(off)
    assert 'moved 3.0 m' in hint and '40 %' in hint and '0.2 %' in hint
    assert 'config/dpn_real_laser.yaml' in hint
    assert survey.hints({**off, 'no_return_reach': 0.0}) == []
    assert _survey(0.0, 0.01, 3.0, lost_every=50).hints(off) == []     # beams that all return
    # Open space seen by an ideal laser: silent beams, but no return lost inside a surface.
    assert _survey(0.0, 0.4, 3.0).hints(off) == []
    # A laser that moves less than the standing distance stands.
    assert _survey(0.0, 0.4, STANDING_DISTANCE).standing
