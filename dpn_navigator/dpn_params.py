"""
Parameters of the ``dpn`` node: declared with descriptors and ranges, read once.

Defaults are those of ``config/dpn.yaml``; the node turns them into the core's frozen
``NavigatorConfig`` and never passes itself into the core.

"""

from dataclasses import dataclass
import math

from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor

from .core import FollowerConfig, NavigatorConfig

BIG = 1e6   # bound of the "any value" ranges [m]

# name: (default, description, (low, high), read_only)
FLOAT_PARAMETERS = {
    'map_width': (40.0, 'Width W of the environment along x [m].', (0.1, BIG), True),
    'map_height': (30.0, 'Height H of the environment along y [m].', (0.1, BIG), True),
    'origin_x': (0.0, "Map-frame x of the environment's lower-left corner [m].",
                 (-BIG, BIG), True),
    'origin_y': (0.0, "Map-frame y of the environment's lower-left corner [m].",
                 (-BIG, BIG), True),
    'resolution': (0.5, 'Grid cell side [m]; the paper uses 0.5.', (0.01, 10.0), True),
    'safety_radius': (0.6, 'f1 radius r: cells this close to a laser hit are obstacles [m].',
                      (0.0, 5.0), True),
    'footprint_radius': (0.35, 'Cells this close to the robot are planned through [m].',
                         (0.0, 2.0), True),
    'obstacle_proximity_cost': (1.0, 'Extra A* cost of a free cell next to an obstacle cell '
                                '[cells]; 0 plans plain shortest paths.', (0.0, 100.0), True),
    'forget_obstacles_after': (10.0, 'With no path for this long, forget the obstacle cells '
                               'out of view and plan again [s]; 0: never (the paper).',
                               (0.0, 3600.0), True),
    'free_evidence_radius': (0.6, 'Conservative free space: explored -> mobile only for cells '
                             'whose disc of this radius once lay inside one scan polygon, '
                             'else steady [m]; 0: the paper.', (0.0, 5.0), True),
    'moving_object_size': (0.7, 'Object-level relabelling: steady cells of scan-segment hits '
                           'within this distance of a hit in surely-free space become mobile '
                           '[m]; 0: off.', (0.0, 10.0), True),
    'segment_gap': (0.3, 'Consecutive laser hits farther apart than this are different '
                    'objects [m].', (0.01, 10.0), True),
    'mobile_expiry': (5.0, 'Mobile cells no hit confirmed for this long and out of view go '
                      'back to explored [s]; 0: never (the paper).', (0.0, 3600.0), True),
    'goal_x': (math.nan, 'Goal x in the map frame [m]; NaN: wait for /compabot/goal_pose.',
               None, True),
    'goal_y': (math.nan, 'Goal y in the map frame [m]; NaN: wait for /compabot/goal_pose.',
               None, True),
    'max_linear_speed': (1.0, 'Forward speed limit [m/s].', (0.01, 5.0), True),
    'max_angular_speed': (1.5, 'Turn rate limit [rad/s].', (0.01, 10.0), True),
    'goal_tolerance': (0.3, 'Distance to the goal that counts as reached [m].', (0.01, 5.0),
                       True),
    'lookahead_distance': (0.6, 'How far ahead on the path the robot aims [m].', (0.1, 10.0),
                           True),
    'laser_x': (0.0, 'Laser position on the base, forward [m].', (-10.0, 10.0), True),
    'laser_y': (0.0, 'Laser position on the base, left [m].', (-10.0, 10.0), True),
    'laser_yaw': (0.0, 'Laser heading on the base [rad].', (-math.pi, math.pi), True),
    'sensor_timeout': (0.5, 'Stop the robot when scan or odometry is older than this [s].',
                       (0.01, 60.0), True),
    'map_publish_period': (0.0, 'Publish the map at most this often [s]; 0: every scan.',
                           (0.0, 60.0), True),
}


@dataclass(frozen=True)
class DpnParameters:
    """The node's parameters, read once at start-up."""

    navigator: NavigatorConfig
    goal: tuple          # (x, y) [m], or None
    sensor_timeout: float
    map_publish_period: float


def declare_parameters(node):
    """
    Declare every parameter of the ``dpn`` node and read them.

    Returns
    -------
    DpnParameters

    Raises
    ------
    ValueError
        When the values do not make a valid navigator configuration.

    """
    values = {}
    for name, (default, description, bounds, read_only) in FLOAT_PARAMETERS.items():
        descriptor = ParameterDescriptor(description=description, read_only=read_only)
        if bounds is not None:
            descriptor.floating_point_range = [
                FloatingPointRange(from_value=bounds[0], to_value=bounds[1], step=0.0)]
        values[name] = float(node.declare_parameter(name, default, descriptor).value)
    follower = FollowerConfig(
        max_linear_speed=values['max_linear_speed'],
        max_angular_speed=values['max_angular_speed'],
        goal_tolerance=values['goal_tolerance'],
        lookahead_distance=values['lookahead_distance'])
    navigator = NavigatorConfig(
        width=values['map_width'], height=values['map_height'],
        origin=(values['origin_x'], values['origin_y']), resolution=values['resolution'],
        safety_radius=values['safety_radius'], footprint_radius=values['footprint_radius'],
        obstacle_proximity_cost=values['obstacle_proximity_cost'],
        forget_obstacles_after=values['forget_obstacles_after'],
        free_evidence_radius=values['free_evidence_radius'],
        moving_object_size=values['moving_object_size'], segment_gap=values['segment_gap'],
        mobile_expiry=values['mobile_expiry'],
        laser_offset=(values['laser_x'], values['laser_y'], values['laser_yaw']),
        follower=follower)
    goal = None
    if math.isfinite(values['goal_x']) and math.isfinite(values['goal_y']):
        goal = (values['goal_x'], values['goal_y'])
    return DpnParameters(navigator, goal, values['sensor_timeout'],
                         values['map_publish_period'])
