"""
A TurtleBot3 Burger in the world, mapped and driven by dpn (issue 29).

The pybullet world simulates the ``turtlebot3_burger`` profile (its body, 0.22 m/s, the LDS-01:
360 degrees, 3.5 m, 5 Hz, with the profile's range noise and dropouts); dpn runs with
``config/dpn_turtlebot3_burger.yaml`` over ``config/dpn.yaml``'s defaults, both nodes in one
process (``tools/drift_episode``). Back_and_forth, task 0: the robot must reach the true goal
with a map whose seen walls are mostly steady and hold no ghost.
"""

from pathlib import Path

from dpn_navigator.tools.drift_episode import run_drift_episode
import pytest
import yaml

CONFIG = Path(__file__).resolve().parents[2] / 'config' / 'dpn_turtlebot3_burger.yaml'


@pytest.mark.slow
def test_dpn_maps_and_drives_a_turtlebot3_burger(ros_context):
    overlay = yaml.safe_load(CONFIG.read_text())['/**/dpn']['ros__parameters']
    result = run_drift_episode(
        ros_context, 'back_and_forth', task=0,
        world_parameters={'robot_profile': 'turtlebot3_burger'}, dpn_parameters=overlay,
        time_limit=450.0, real_time_factor=8.0)
    assert result.pose_source == 'tf'
    assert result.reported_reached, result
    assert result.true_goal_distance < overlay['xy_goal_tolerance'] + 0.05
    assert result.contacts == 0
    assert result.ghost_cells == 0
    # 0.89-0.92 measured (the episode runs on wall-clock timers at 8x, so it varies): the
    # profile's dropouts and mixed pixels turn some wall cells mobile
    # (docs/simulator.md#robot-profiles); the ideal laser's runs give 0.99.
    assert result.seen_wall_steady > 0.85
