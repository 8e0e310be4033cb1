"""The side-by-side report of several navigators' logs: tables, ratios, shortfalls, figure."""

import json

from dpn_navigator.benchmark.compare_report import (common_episodes, compare_markdown,
                                                    load_runs, main, paired_outcomes,
                                                    ratio_matrix, save_compare_figure,
                                                    sign_test)
from dpn_navigator.benchmark.episode_log import EpisodeLog
import numpy as np
import pytest
from test_benchmark_protocol import make_row


def runs():
    """Two maps x wanderers 0 and 5, two seeds each, for dpn and the oracle."""
    outcome = {
        # (navigator, map, wanderers): failures of seeds 1 and 2
        ('dpn', 'maze', 0): ('', ''), ('oracle', 'maze', 0): ('', ''),
        ('dpn', 'maze', 5): ('', 'no_path'), ('oracle', 'maze', 5): ('', ''),
        ('dpn', 'back_and_forth', 0): ('', ''), ('oracle', 'back_and_forth', 0): ('', ''),
        ('dpn', 'back_and_forth', 5): ('timeout', 'timeout'),
        ('oracle', 'back_and_forth', 5): ('timeout', 'timeout'),
    }
    rows = {'dpn': [], 'oracle': []}
    for (navigator, map_name, count), failures in outcome.items():
        for seed, failure in zip((1, 2), failures):
            rows[navigator].append(make_row(map_name, 15 if map_name == 'maze' else 3,
                                            wanderers=count, seed=seed, failure=failure))
    return rows


def test_ratio_matrix_divides_by_what_was_possible():
    rows = runs()
    ratios, counts, maps = ratio_matrix(rows['dpn'], rows['oracle'])
    assert counts == [0, 5] and [m[0] for m in maps] == ['back_and_forth', 'maze']
    # back_and_forth with 5 wanderers: the oracle never succeeded, so no ratio.
    np.testing.assert_array_equal(ratios, [[1.0, 1.0], [np.nan, 0.5]])


def test_compare_markdown_tables_and_shortfalls():
    rows = runs()
    text = compare_markdown(rows, dropped=3)
    assert '8 episodes per navigator (2 maps)' in text and '3 rows held by some' in text
    assert '| dpn | 100.0 | 25.0 | 62.5 | 2 | 1 | 0 |' in text
    assert '| oracle | 100.0 | 50.0 | 75.0 | 2 | 0 | 0 |' in text
    assert '| 3 back_and_forth | 50 | 50 |' in text and '| 15 maze | 75 | 100 |' in text
    assert 'Overall dpn / oracle: 0.833.' in text
    assert '| 3 back_and_forth | 1.00 | - | 1.00 |' in text
    assert '| 15 maze | 1.00 | 0.50 | 0.75 |' in text
    assert '| oracle | 0 / 0 | 0 / 1 | **0 / 1** | 1 |' in text
    assert '| 15 maze | 5 | 50 | 100 | no_path |' in text
    assert 'Nowhere.' in compare_markdown(rows, threshold=0.4)
    # Without the oracle there is no ratio section.
    assert 'dpn / oracle' not in compare_markdown({'dpn': rows['dpn']})


def test_common_episodes_keeps_only_shared_keys():
    rows = runs()
    rows['oracle'].append(make_row('maze', 15, wanderers=10, seed=9))
    kept, dropped = common_episodes(rows)
    assert dropped == 1 and len(kept['oracle']) == len(kept['dpn']) == 8


def write_run(folder, navigator, rows):
    """Write an output folder as dpn-benchmark does."""
    folder.mkdir()
    (folder / 'run.json').write_text(json.dumps({'navigator': navigator}))
    with EpisodeLog(folder / 'episodes.csv') as log:
        for row in rows:
            log.append(row)


def test_main_writes_table_and_figure(tmp_path, capsys):
    rows = runs()
    write_run(tmp_path / 'a', 'dpn', rows['dpn'])
    write_run(tmp_path / 'b', 'oracle', rows['oracle'])
    assert main([str(tmp_path / 'a'), str(tmp_path / 'b'), '--out', str(tmp_path / 'r')]) == 0
    assert '| 15 maze | 5 | 50 | 100 | no_path |' in (tmp_path / 'r' / 'compare.md').read_text()
    assert (tmp_path / 'r' / 'compare.png').read_bytes()[:4] == b'\x89PNG'
    assert 'wrote' in capsys.readouterr().out
    assert set(load_runs([tmp_path / 'a', tmp_path / 'b'])) == {'dpn', 'oracle'}


def test_bad_folders_are_refused(tmp_path, capsys):
    rows = runs()
    write_run(tmp_path / 'a', 'dpn', rows['dpn'])
    write_run(tmp_path / 'b', 'dpn', rows['dpn'])
    with pytest.raises(SystemExit) as exited:
        main([str(tmp_path / 'a'), str(tmp_path / 'b'), '--out', str(tmp_path / 'r')])
    assert exited.value.code == 2 and 'two folders hold the dpn' in capsys.readouterr().err
    with pytest.raises(ValueError, match='holds no episodes.csv'):
        load_runs([tmp_path / 'nothing'])
    with pytest.raises(ValueError, match='no episodes'):
        save_compare_figure(tmp_path / 'x.png', {'dpn': []})


def test_paired_outcomes_count_the_episodes_only_one_navigator_won():
    rows = runs()
    assert paired_outcomes(rows['dpn'], rows['oracle']) == {0: (0, 0), 5: (0, 1)}
    assert paired_outcomes(rows['oracle'], rows['dpn']) == {0: (0, 0), 5: (1, 0)}
    # An episode the other did not run is not compared.
    extra = rows['dpn'] + [make_row('maze', 15, wanderers=5, seed=7, failure='timeout')]
    assert paired_outcomes(extra, rows['oracle']) == {0: (0, 0), 5: (0, 1)}


@pytest.mark.parametrize('won, lost, p', [(0, 0, 1.0), (1, 0, 1.0), (5, 0, 0.0625),
                                          (0, 5, 0.0625), (9, 1, 0.021484375),
                                          (3, 3, 1.0), (10, 0, 2.0 / 1024)])
def test_sign_test_is_the_exact_binomial_tail(won, lost, p):
    assert sign_test(won, lost) == pytest.approx(p)
