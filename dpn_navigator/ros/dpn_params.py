"""
Parameters of the ``dpn`` node: declared with descriptors and ranges, read once.

Defaults are those of ``config/dpn.yaml`` (the Husky on back_and_forth, task 0; a test keeps
them equal); the node turns them into the core's frozen ``NavigatorConfig`` and never passes
itself into the core. Number parameters take integers too (``-p map_width:=25``).

"""

from dataclasses import dataclass
import math

from rcl_interfaces.msg import IntegerRange, ParameterDescriptor

from .parameter_declaration import declare_number
from ..core import FollowerConfig, GridGeometry, NavigatorConfig
from ..core.cell_label import OCCUPANCY_MOBILE_OBSTACLE

BIG = 1e6   # bound of the "any value" ranges [m]
#: Most grid cells a node may ask for (2048 x 2048): the grid and A*'s arrays stay in memory and
#: one plan in seconds. More is a parameter error, not a MemoryError in numpy.
MAX_GRID_CELLS = 2048 * 2048
#: Largest fine free-evidence grid (2 bytes a cell: 134 MB; 819 m x 819 m at 0.1 m).
MAX_FINE_GRID_CELLS = 8192 * 8192

# name: (default, description, (low, high), read_only)
FLOAT_PARAMETERS = {
    'map_width': (25.0, 'Width W of the environment along x [m].', (0.1, BIG), True),
    'map_height': (20.0, 'Height H of the environment along y [m].', (0.1, BIG), True),
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
    'evidence_margin': (0.15, 'A hit shows motion only within free_evidence_radius minus '
                        'this of a cell surely seen free [m].', (0.0, 5.0), True),
    'segment_gap': (0.3, 'Consecutive laser hits farther apart than this are different '
                    'objects [m].', (0.01, 10.0), True),
    'fine_evidence_resolution': (0.1, 'Fine free evidence: a hit also shows motion when its '
                                 'cell of a grid this fine was once surely seen free with '
                                 'fine_evidence_radius [m]; 0: off (the paper).', (0.0, 5.0),
                                 True),
    'fine_evidence_radius': (0.2, 'Fine free evidence: a fine cell is surely free when its '
                             'disc of this radius lay inside one scan polygon [m]; 0: off.',
                             (0.0, 5.0), True),
    'fine_evidence_range': (20.0, 'Fine free evidence: fine cells are marked surely free only '
                            'within this distance of the laser, where the beams are closer '
                            'together than the fine cells [m].', (0.01, 1000.0), True),
    'mobile_expiry': (3.0, 'Mobile cells no hit confirmed for this long and out of view go '
                      'back to explored [s]; 0: never (the paper).', (0.0, 3600.0), True),
    'track_confirm_time': (5.0, 'Motion tracks: a compact free-standing segment near a moving '
                           'object stays mobile while motion was seen within this long [s]; '
                           '0: off.', (0.0, 3600.0), True),
    'track_still_distance': (0.08, 'Still objects: a compact segment this close to where one '
                             'stood 0.8-1.5 s ago is not seen to move by the places left '
                             'empty near it, nor continues a track that never moved [m]; 0: '
                             'off.', (0.0, 10.0), True),
    'trail_distance': (1.2, 'Trails: out-of-view mobile cells whose followed object the scan '
                       'sees at least this far away go back to explored [m]; 0: off.',
                       (0.0, 100.0), True),
    'object_memory': (5.0, 'Object memory: steady cells of small objects (scan segments up '
                      'to 1 m with 3 hits or more) that no longer segment has hit are '
                      'forgotten after this long without a hit, out of view and more than 2 '
                      'safety radii away [s]; 0: off.', (0.0, 3600.0), True),
    'robot_length': (0.99, 'Robot footprint along x, centred on the base [m].', (0.01, 10.0),
                     True),
    'robot_width': (0.67, 'Robot footprint along y, centred on the base [m].', (0.01, 10.0),
                    True),
    'turn_sweep_memory': (2.0, 'Turn sweep: a turn in place is tested against the laser hits '
                          'kept around the robot, and replaced by a move to a place where it '
                          'is clear, or held, when its corners would hit one; a kept hit '
                          'counts this long, then while the grid labels its cell an obstacle '
                          '[s]; 0: off.', (0.0, 60.0), True),
    'turn_sweep_margin': (0.05, 'Clearance the turn sweep keeps from the laser hits [m].',
                          (0.0, 1.0), True),
    'turn_sweep_spot_distance': (0.6, 'Farthest place the turn sweep moves the robot to for a '
                                 'blocked turn [m]; 0: it waits.', (0.0, 5.0), True),
    'goal_x': (2.0, 'Goal x in the map frame [m]; NaN: wait for a goal on goal_pose.',
               None, True),
    'goal_y': (18.0, 'Goal y in the map frame [m]; NaN: wait for a goal on goal_pose.',
               None, True),
    'max_linear_speed': (1.0, 'Forward speed limit [m/s].', (0.01, 5.0), True),
    'max_angular_speed': (1.5, 'Turn rate limit [rad/s].', (0.01, 10.0), True),
    'goal_tolerance': (0.3, 'Distance to the goal that counts as reached [m].', (0.01, 5.0),
                       True),
    'lookahead_distance': (0.6, 'How far ahead on the path the robot aims [m].', (0.1, 10.0),
                           True),
    'laser_x': (0.337, 'Laser position on the base, forward [m].', (-10.0, 10.0), True),
    'laser_y': (0.0, 'Laser position on the base, left [m].', (-10.0, 10.0), True),
    'laser_yaw': (0.0, 'Laser heading on the base [rad].', (-math.pi, math.pi), True),
    'sensor_timeout': (0.4, 'Stop the robot when scan or odometry is older than this [s], on '
                       'the node clock or the steady clock.', (0.01, 60.0), True),
    'map_publish_period': (0.0, 'Publish the map at most this often [s]; 0: every scan.',
                           (0.0, 60.0), True),
    'marker_min_period': (0.2, 'Send the markers and plan at most this often on replans and '
                          'status changes [s] (a later one waits for the period); 0: on every '
                          'one. They also go out every 0.5 s.', (0.0, 60.0), True),
}

# name: (default, description); read-only, typed by the default.
OTHER_PARAMETERS = {
    'map_frame': ('map', 'Frame of the map, the plan and the markers; goals in another frame are '
                  'rejected (an empty goal frame means this one).'),
    'laser_frame': ('laser', 'Frame the scans must be in (laser_x/_y/_yaw place it on the '
                    "base); scans in another frame are rejected and counted; '': any."),
    'base_frame': ('base_link', 'Frame of the robot base: header of TwistStamped commands.'),
    'cmd_vel_stamped': (False, 'Send geometry_msgs/TwistStamped on cmd_vel instead of Twist '
                        "(Jazzy's diff_drive_controller takes TwistStamped)."),
    'object_min_hits': (3, 'Thin things: a free-standing laser segment of fewer hits shows no '
                        'motion and is not followed (a post thinner than the beam spacing '
                        'slips between the beams) [hits]; 0: off (the paper).'),
    'track_exclusive': (True, 'Exclusive motion tracks: at most one scan segment continues a '
                        'track per scan (false: the paper has no tracks; before, a post next '
                        'to a wanderer shared its track).'),
    'object_memory_short_segments': (True, 'Short segments in the object memory: steady cells '
                                     'that only laser segments of one or two hits have hit (a '
                                     'wanderer glimpsed far off through a gap) are forgotten '
                                     'as object_memory forgets small objects (false: kept).'),
    'map_mobile_value': (OCCUPANCY_MOBILE_OBSTACLE, 'OccupancyGrid value of mobile-obstacle '
                         'cells in map, 1 to 100 (steady obstacles are 100).'),
    'map_updates': (True, 'On the scans between full maps (map_publish_period > 0), publish the '
                    'box of cells changed since the last map or update on map_updates '
                    '(map_msgs/OccupancyGridUpdate); false: nothing between full maps.'),
}
MOBILE_VALUE_RANGE = (1, 100)
#: The parameters of ``OTHER_PARAMETERS`` that go to the navigator's configuration, not to
#: ``DpnParameters``.
NAVIGATOR_SWITCHES = ('track_exclusive', 'object_min_hits', 'object_memory_short_segments')
#: Allowed ``object_min_hits`` (as ``max_beams``: no more hits than beams).
MIN_HITS_RANGE = (0, 1_000_000)


@dataclass(frozen=True)
class DpnParameters:
    """The node's parameters, read once at start-up."""

    navigator: NavigatorConfig
    goal: tuple          # (x, y) [m], or None
    sensor_timeout: float
    map_publish_period: float
    marker_min_period: float = 0.2
    map_frame: str = 'map'
    laser_frame: str = 'laser'
    base_frame: str = 'base_link'
    cmd_vel_stamped: bool = False
    map_mobile_value: int = OCCUPANCY_MOBILE_OBSTACLE
    map_updates: bool = True


def declare_parameters(node):
    """
    Declare every parameter of the ``dpn`` node and read them.

    Returns
    -------
    DpnParameters

    Raises
    ------
    ValueError
        When a value is not a number where one is due, is out of range, the values do not make
        a valid navigator configuration, or they ask for a grid of more than ``MAX_GRID_CELLS``
        cells.

    """
    values = {name: declare_number(node, name, default, description, bounds, read_only)
              for name, (default, description, bounds, read_only) in FLOAT_PARAMETERS.items()}
    check_grid_size(values['map_width'], values['map_height'], values['resolution'])
    if values['fine_evidence_resolution'] > 0.0:
        check_grid_size(values['map_width'], values['map_height'],
                        values['fine_evidence_resolution'], MAX_FINE_GRID_CELLS,
                        'fine_evidence_resolution')
    for name, (default, description) in OTHER_PARAMETERS.items():
        descriptor = ParameterDescriptor(description=description, read_only=True)
        if name == 'map_mobile_value':
            descriptor.integer_range = [IntegerRange(
                from_value=MOBILE_VALUE_RANGE[0], to_value=MOBILE_VALUE_RANGE[1], step=1)]
        if name == 'object_min_hits':
            descriptor.integer_range = [IntegerRange(
                from_value=MIN_HITS_RANGE[0], to_value=MIN_HITS_RANGE[1], step=1)]
        values[name] = node.declare_parameter(name, default, descriptor).value
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
        moving_object_size=values['moving_object_size'],
        evidence_margin=values['evidence_margin'], segment_gap=values['segment_gap'],
        object_min_hits=values['object_min_hits'],
        fine_evidence_resolution=values['fine_evidence_resolution'],
        fine_evidence_radius=values['fine_evidence_radius'],
        fine_evidence_range=values['fine_evidence_range'],
        mobile_expiry=values['mobile_expiry'],
        track_confirm_time=values['track_confirm_time'],
        track_still_distance=values['track_still_distance'],
        track_exclusive=values['track_exclusive'],
        trail_distance=values['trail_distance'], object_memory=values['object_memory'],
        object_memory_short_segments=values['object_memory_short_segments'],
        robot_length=values['robot_length'], robot_width=values['robot_width'],
        turn_sweep_memory=values['turn_sweep_memory'],
        turn_sweep_margin=values['turn_sweep_margin'],
        turn_sweep_spot_distance=values['turn_sweep_spot_distance'],
        laser_offset=(values['laser_x'], values['laser_y'], values['laser_yaw']),
        follower=follower)
    goal = None
    if math.isfinite(values['goal_x']) and math.isfinite(values['goal_y']):
        goal = (values['goal_x'], values['goal_y'])
    return DpnParameters(
        navigator, goal, values['sensor_timeout'], values['map_publish_period'],
        values['marker_min_period'],
        **{name: values[name] for name in OTHER_PARAMETERS if name not in NAVIGATOR_SWITCHES})


def check_grid_size(width, height, resolution, max_cells=MAX_GRID_CELLS,
                    resolution_name='resolution'):
    """
    Refuse a grid of more than ``max_cells`` cells before anything is allocated.

    Parameters
    ----------
    width, height, resolution : float
        The ``map_width``, ``map_height`` and ``resolution`` parameters [m].
    max_cells : int
        ``MAX_GRID_CELLS`` for the label grid, ``MAX_FINE_GRID_CELLS`` for the fine free
        evidence.
    resolution_name : str
        The parameter ``resolution`` came from, for the message.

    Raises
    ------
    ValueError
        Naming the parameters and the cell count.

    """
    geometry = GridGeometry(width, height, resolution)
    cells = geometry.rows * geometry.cols
    if cells > max_cells:
        hint = (' (or fine_evidence_resolution 0 and fine_evidence_radius 0: no fine evidence)'
                if resolution_name != 'resolution' else '')
        raise ValueError(
            f'map_width {width:g} m x map_height {height:g} m at {resolution_name} '
            f'{resolution:g} m is {geometry.cols} x {geometry.rows} = {cells:,} cells, more '
            f'than {max_cells:,}: use a coarser {resolution_name} or a smaller map{hint}')
