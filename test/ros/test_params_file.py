"""``ros/params_file``: a params YAML read for the dpn node and checked as the node does."""

from pathlib import Path

from dpn_navigator.core.mapping.label_grid import LabelRule
from dpn_navigator.ros.params_file import dpn_parameters, node_values, ParamsFileError
import pytest

REPO_CONFIG = Path(__file__).resolve().parents[2] / 'config'


def write(tmp_path, text):
    path = tmp_path / 'params.yaml'
    path.write_text(text)
    return path


@pytest.mark.parametrize('key', ['dpn', '/dpn', '/**/dpn', '/robot2/dpn'])
def test_the_nodes_key_wins_over_the_wildcard(tmp_path, key):
    path = write(tmp_path, f'/**:\n  ros__parameters:\n    resolution: 0.25\n    map_width: 9\n'
                           f'{key}:\n  ros__parameters:\n    map_width: 30.0\n'
                           'other_node:\n  ros__parameters:\n    map_height: 1.0\n')
    assert node_values(path) == {'resolution': 0.25, 'map_width': 30.0}


def test_the_shipped_files_read_as_the_node_reads_them():
    params, limits = dpn_parameters(node_values(REPO_CONFIG / 'dpn.yaml'))
    assert params.navigator.width == 25.0 and limits.max_beams == 4096
    paper, _ = dpn_parameters(node_values(REPO_CONFIG / 'dpn_paper.yaml'))
    assert paper.navigator.label_rule() == LabelRule()


@pytest.mark.parametrize('text, message', [
    ('dpn: [1, 2\n', 'not valid YAML'),
    ('- 1\n', 'holds no node keys'),
    ('dpn:\n  map_width: 3\n', "no 'ros__parameters:' mapping"),
    ('other:\n  ros__parameters:\n    map_width: 3\n', "no parameters for the node 'dpn'"),
])
def test_malformed_files_are_one_clear_error(tmp_path, text, message):
    with pytest.raises(ParamsFileError, match=message):
        node_values(write(tmp_path, text))


def test_a_missing_file_is_a_clear_error(tmp_path):
    with pytest.raises(ParamsFileError, match='cannot read the params file'):
        node_values(tmp_path / 'none.yaml')


@pytest.mark.parametrize('values, message', [
    ({'map_width': 'wide'}, 'parameter map_width must be a number'),
    ({'resolution': 0.001}, 'resolution'),
    ({'max_beams': 2.5}, 'max_beams'),
    ({'map_width': 2e5}, 'cells, more than'),
])
def test_values_are_checked_as_the_node_checks_them(values, message):
    with pytest.raises(ParamsFileError, match=message):
        dpn_parameters(values)


def test_unknown_names_are_ignored_as_the_node_ignores_them():
    params, _ = dpn_parameters({'no_such_parameter': 1.0, 'map_height': 12})
    assert params.navigator.height == 12.0
