"""
One episode of the pybullet world and the dpn node in one process, with drifting odometry.

Both nodes run in one executor over DDS (a domain of the caller's choice); the world's odometry
drifts as its ``odom_drift_*`` parameters say and its ``map -> odom`` plays a localiser. After
every scan the navigator's labels are compared with the walls: the wall cells ever labelled
mobile (a drifting wall erases itself through the mobile label), the seen wall cells labelled
steady at the end, and the ghost cells (steady obstacles where there is no wall). The episode
ends when the navigator reports the goal reached or the simulated time runs out; the distance
from the *true* pose to the goal says whether it really got there.

``python -m dpn_navigator.tools.drift_episode --drift 0.02 0.01 0.0044`` runs one and prints
the measures (``--help``). Used by ``test/ros/test_drift_episode.py``.

"""

import argparse
from dataclasses import asdict, dataclass
import json
import math
import time

import numpy as np
import yaml


@dataclass
class DriftEpisodeResult:
    """What one episode measured; distances [m], times [s]."""

    reported_reached: bool
    status: str
    true_goal_distance: float
    odometry_error: float
    odometry_yaw_error: float
    wall_cells_ever_mobile: int
    seen_wall_steady: float
    ghost_cells: int
    contacts: int
    sim_time: float
    pose_source: str
    scans_skipped: int


def run_drift_episode(context, scenario='back_and_forth', task=0, wanderers=0, seed=0,
                      world_parameters=None, dpn_parameters=None, time_limit=150.0,
                      wall_limit=600.0, real_time_factor=3.0):
    """
    Run one episode; return a `DriftEpisodeResult`.

    Parameters
    ----------
    context : rclpy.context.Context
        An initialised context (its domain id is the caller's).
    scenario, task, wanderers, seed
        As the world node's parameters.
    world_parameters, dpn_parameters : dict, optional
        More parameters of either node (e.g. ``odom_drift_scale``, ``pose_source``).
    time_limit, wall_limit : float
        Simulated and wall-clock limits [s].
    real_time_factor : float
        The world's pace.

    """
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.parameter import Parameter
    from sim_bridge.husky import LASER_MOUNT
    from sim_bridge.pybullet_world_node import PybulletWorldNode
    from sim_bridge.scenario import load_scenario

    from ..benchmark.ground_truth import wall_belt
    from ..core.cell_label import CellLabel
    from ..core.navigator import NavigatorStatus
    from ..ros.dpn_node import DpnNode

    loaded = load_scenario(scenario)
    goal = loaded.tasks[task].goal
    world_values = {'scenario': scenario, 'task': task, 'wanderers': wanderers, 'seed': seed,
                    'real_time_factor': float(real_time_factor), **(world_parameters or {})}
    dpn_values = {'map_width': loaded.width, 'map_height': loaded.height,
                  'origin_x': loaded.origin[0], 'origin_y': loaded.origin[1],
                  'use_default_goal': True, 'goal_x': goal[0], 'goal_y': goal[1],
                  'laser_x': LASER_MOUNT[0], 'laser_y': LASER_MOUNT[1],
                  'laser_yaw': LASER_MOUNT[2], 'use_sim_time': True,
                  # The map is known and measured cell by cell against the truth: fixed.
                  'map_growth_step': 0.0, **(dpn_parameters or {})}
    world = PybulletWorldNode(context=context, parameter_overrides=[
        Parameter(k, value=v) for k, v in world_values.items()])
    dpn = DpnNode(context=context, parameter_overrides=[
        Parameter(k, value=float(v) if isinstance(v, int) and not isinstance(v, bool) else v)
        for k, v in dpn_values.items()])
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(world)
    executor.add_node(dpn)
    geometry = dpn.navigator.grid.geometry
    radius = dpn.params.navigator.safety_radius
    belt = wall_belt(loaded.occupied, loaded.geometry, geometry, radius)
    # Beyond this band a steady cell explains no wall: a ghost.
    near = wall_belt(loaded.occupied, loaded.geometry, geometry, radius + geometry.resolution)
    ever_mobile = np.zeros(geometry.shape, dtype=bool)
    last_scan_time = -1.0
    deadline = time.monotonic() + wall_limit
    try:
        while time.monotonic() < deadline and world.world.time < time_limit:
            executor.spin_once(timeout_sec=0.01)
            if world.world.time - last_scan_time >= 0.1:
                last_scan_time = world.world.time
                ever_mobile |= dpn.navigator.grid.labels == CellLabel.MOBILE_OBSTACLE
            if dpn.navigator.status is NavigatorStatus.GOAL_REACHED:
                break
        labels = dpn.navigator.grid.labels
        seen_walls = belt & (labels != CellLabel.NON_EXPLORED)
        true_pose = world.world.husky_pose
        odom_pose = world.odometry.pose
        return DriftEpisodeResult(
            reported_reached=dpn.navigator.status is NavigatorStatus.GOAL_REACHED,
            status=dpn.navigator.status.value,
            true_goal_distance=math.dist(true_pose[:2], goal),
            odometry_error=math.dist(true_pose[:2], odom_pose[:2]),
            odometry_yaw_error=abs(math.remainder(true_pose[2] - odom_pose[2], math.tau)),
            wall_cells_ever_mobile=int(np.count_nonzero(ever_mobile & belt)),
            seen_wall_steady=(float(np.count_nonzero(seen_walls
                                                     & (labels == CellLabel.STEADY_OBSTACLE)))
                              / max(1, int(np.count_nonzero(seen_walls)))),
            ghost_cells=int(np.count_nonzero((labels == CellLabel.STEADY_OBSTACLE) & ~near)),
            contacts=world.world.contacts.events,
            sim_time=world.world.time,
            pose_source=dpn.placer.source or '',
            scans_skipped=dpn.scans_skipped)
    finally:
        executor.shutdown()
        dpn.destroy_node()
        world.destroy_node()


def main(args=None):
    """Run one drift episode from the command line and print its result as JSON."""
    import os
    import rclpy
    from rclpy.context import Context
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[1])
    parser.add_argument('--scenario', default='back_and_forth')
    parser.add_argument('--task', type=int, default=0)
    parser.add_argument('--wanderers', type=int, default=0)
    parser.add_argument('--seed', type=int, default=0)
    parser.add_argument('--drift', type=float, nargs=3, default=(0.0, 0.0, 0.0),
                        metavar=('SCALE', 'YAW_SCALE', 'YAW_PER_METRE'),
                        help='odometry errors: distance scale, turn scale, rad per metre')
    parser.add_argument('--localiser-error', type=float, nargs=2, default=(0.0, 0.0),
                        metavar=('XY', 'YAW'), help='[m], [rad]')
    parser.add_argument('--pose-source', default='auto', choices=('auto', 'tf', 'odom'))
    parser.add_argument('--time-limit', type=float, default=150.0)
    parser.add_argument('--real-time-factor', type=float, default=3.0)
    parser.add_argument('--dpn-param', action='append', default=[], metavar='NAME:=VALUE',
                        help='a parameter of the dpn node, as on a ros2 command line '
                             '(e.g. goal_approach_margin:=0.0); may repeat')
    parser.add_argument('--world-param', action='append', default=[], metavar='NAME:=VALUE',
                        help='a parameter of the world node (e.g. laser_profile:=rplidar_a2, '
                             'laser_upside_down:=true); may repeat')
    options = parser.parse_args(args)
    dpn_parameters = {'pose_source': options.pose_source}
    world_parameters = {'odom_drift_scale': options.drift[0],
                        'odom_drift_yaw_scale': options.drift[1],
                        'odom_drift_yaw_per_metre': options.drift[2],
                        'localiser_error_xy': options.localiser_error[0],
                        'localiser_error_yaw': options.localiser_error[1]}
    for option, values, target in (('--dpn-param', options.dpn_param, dpn_parameters),
                                   ('--world-param', options.world_param, world_parameters)):
        for assignment in values:
            name, separator, text = assignment.partition(':=')
            if not separator or not name:
                parser.error(f'{option} wants NAME:=VALUE, got {assignment!r}')
            target[name] = yaml.safe_load(text)
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    context = Context()
    rclpy.init(context=context)
    try:
        result = run_drift_episode(
            context, options.scenario, options.task, options.wanderers, options.seed,
            world_parameters=world_parameters, dpn_parameters=dpn_parameters,
            time_limit=options.time_limit, real_time_factor=options.real_time_factor)
    finally:
        rclpy.try_shutdown(context=context)
    print(json.dumps(asdict(result)))


if __name__ == '__main__':
    main()
