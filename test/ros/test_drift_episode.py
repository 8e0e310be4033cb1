"""
End to end in one process (issue 29): drifting odometry with a localiser, a TF-only laser mount.

The pybullet world and the dpn node run in one executor over DDS (``tools/drift_episode``).
Measures: the distance from the *true* pose to the goal, the wall cells ever labelled mobile,
the steady share of the seen wall cells and the ghost cells (steady where no wall is).
"""

from dpn_navigator.tools.drift_episode import run_drift_episode
import pytest

#: The navigator's goal tolerance (0.3 m) and a margin for the last tick's motion.
REACHED = 0.35


@pytest.mark.slow
def test_two_percent_drift_with_a_perfect_localiser_reaches_the_true_goal(ros_context):
    result = run_drift_episode(
        ros_context, 'back_and_forth', task=0, world_parameters={
            'odom_drift_scale': 0.02, 'odom_drift_yaw_scale': 0.01,
            'odom_drift_yaw_per_metre': 0.00436})      # 2 % / 1 % / 0.25 deg per metre
    assert result.pose_source == 'tf'
    assert result.odometry_error > 1.0                 # the odometry did drift
    assert result.reported_reached and result.true_goal_distance < REACHED
    assert result.wall_cells_ever_mobile <= 10
    assert result.seen_wall_steady > 0.95
    assert result.ghost_cells == 0 and result.contacts == 0


@pytest.mark.slow
@pytest.mark.parametrize('seed', [0, 1])
def test_a_localiser_off_by_5_cm_and_1_degree_still_reaches_the_true_goal(ros_context, seed):
    # The localiser's estimate is off by a fixed 5 cm and 1 deg in the robot's frame (the
    # seed turns the 5 cm): the node's free evidence renewal keeps the walls, its goal
    # approach margin the true distance (before: a false arrival 0.33 m off with seed 0, and
    # still driving at 150 s with 266 walls ever mobile with seed 1).
    result = run_drift_episode(
        ros_context, 'back_and_forth', task=0, seed=seed, world_parameters={
            'odom_drift_scale': 0.02, 'odom_drift_yaw_scale': 0.01,
            'odom_drift_yaw_per_metre': 0.00436, 'localiser_error_xy': 0.05,
            'localiser_error_yaw': 0.01745})
    assert result.pose_source == 'tf'
    assert result.reported_reached and result.true_goal_distance < 0.3
    assert result.wall_cells_ever_mobile <= 20
    assert result.seen_wall_steady > 0.95
    assert result.ghost_cells == 0 and result.contacts == 0


@pytest.mark.slow
def test_an_upside_down_laser_known_only_from_tf_maps_right_and_reaches_the_goal(ros_context):
    # The world's laser: upside down, 0.2 m forward, 0.05 m left; dpn's laser_* parameters
    # keep the Husky's upright mount at 0.337 m, so only TF tells the truth.
    result = run_drift_episode(
        ros_context, 'back_and_forth', task=0, world_parameters={
            'laser_upside_down': True, 'laser_x': 0.2, 'laser_y': 0.05})
    assert result.pose_source == 'tf'
    assert result.reported_reached and result.true_goal_distance < REACHED
    assert result.ghost_cells == 0 and result.wall_cells_ever_mobile == 0
    assert result.seen_wall_steady > 0.95 and result.contacts == 0
