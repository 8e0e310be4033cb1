"""Episode logs of versions 1 and 2 still read (new columns None) and are never resumed."""

import csv

from dpn_navigator.benchmark.episode_log import COLUMNS, CONTACT_KIND_COLUMNS, EpisodeLog
from dpn_navigator.benchmark.episode_log import LEGACY_COLUMNS, read_log, VERSION2_COLUMNS
from dpn_navigator.benchmark.metrics_report import (detection_distribution_markdown,
                                                    standard_metrics_markdown)
from dpn_navigator.benchmark.report import summary_markdown
import pytest
from test_benchmark_protocol import make_row


def write_legacy(path, rows, columns=LEGACY_COLUMNS):
    with open(path, 'w', newline='') as stream:
        writer = csv.writer(stream, lineterminator='\n')
        writer.writerow(columns)
        for row in rows:
            writer.writerow(['' if row[c] is None else int(row[c]) if c == 'success' else row[c]
                             for c in columns])


def test_a_version_1_log_reads_and_reports_but_is_not_resumed(tmp_path):
    path = tmp_path / 'episodes.csv'
    rows = [make_row(seed=1), make_row(seed=2, failure='no_path')]
    for row in rows:
        for column in set(COLUMNS) - set(LEGACY_COLUMNS):
            row[column] = None
        for column in LEGACY_COLUMNS[19:-2]:
            row[column] = None
    write_legacy(path, rows)
    read = read_log(path)
    assert [row['success'] for row in read] == [1, 0]
    assert all(row['end_reason'] is None and row['spl'] is None for row in read)
    text = summary_markdown(read)
    assert '| dpn | 2 | 50.0 [' in text and '| - | - |' in text
    # SPL and the BARN score come from the version-1 columns: (11 / 12.5 + 0) / 2 = 0.44, and
    # 11 / clip(10, 22, 88) / 2 = 0.25.
    assert '| 0.440 [' in text and '| 0.250 [' in text
    with pytest.raises(ValueError, match='version-1'):
        EpisodeLog(path)


def test_a_log_of_this_version_round_trips_the_new_columns(tmp_path):
    path = tmp_path / 'episodes.csv'
    with EpisodeLog(path) as log:
        log.append(make_row(seed=1, barn_score=0.25, mobile_precision=None, scans=10,
                            mobile_precision_all=0.5, wanderers=5))
        log.append(make_row(seed=2, failure='timeout', wanderers=5, scans=10,
                            mobile_precision=1.0, mobile_precision_all=None))
    read = read_log(path)
    assert read[0]['end_reason'] == '' and read[1]['end_reason'] == 'timeout_moving'
    assert read[0]['barn_score'] == 0.25 and read[0]['spl'] == pytest.approx(0.88)
    text = standard_metrics_markdown({'dpn': read})
    assert '| dpn | 2 | 50.0 [' in text
    # The timeout is counted under its benchmark reason (last column).
    assert text.rstrip().endswith('| 1 |')
    detection = detection_distribution_markdown({'dpn': read})
    # One episode leaves precision undefined: counted as such, not as 1.
    assert '| dpn | 5 | 2 | 1 | 1.000 [1.000, 1.000] | 0.500 [0.500, 0.500] |' in detection


def test_a_version_2_log_reads_without_the_contact_kinds_and_is_not_resumed(tmp_path):
    path = tmp_path / 'episodes.csv'
    write_legacy(path, [make_row(seed=1), make_row(seed=2, failure='collision',
                                                   wanderer_contacts=2)], VERSION2_COLUMNS)
    read = read_log(path)
    assert [row['wanderer_contacts'] for row in read] == [0, 2]
    assert all(row[column] is None for row in read for column in CONTACT_KIND_COLUMNS)
    assert 'robot-caused / agent-caused -.' in summary_markdown(read)
    with pytest.raises(ValueError, match='version-2'):
        EpisodeLog(path)


def test_the_contact_kinds_round_trip_and_are_summed_in_the_summary(tmp_path):
    path = tmp_path / 'episodes.csv'
    with EpisodeLog(path) as log:
        log.append(make_row(seed=1, failure='collision', wanderer_contacts=3,
                            robot_caused_contacts=1, agent_caused_contacts=2, wanderers=5))
        log.append(make_row(seed=2, failure='collision', wanderer_contacts=1,
                            robot_caused_contacts=1, agent_caused_contacts=0, wanderers=5))
    read = read_log(path)
    assert [(row['robot_caused_contacts'], row['agent_caused_contacts']) for row in read] == \
        [(1, 2), (1, 0)]
    text = summary_markdown(read)
    assert 'robot-caused / agent-caused 2 / 2.' in text
    assert '| 0 / 2 | 2 / 2 |' in text      # episodes with contacts wall / wanderer; events
