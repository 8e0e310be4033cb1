"""
Parameters of the ``dpn`` node: declared with descriptors and ranges, read once.

Each parameter is stated once: the core's configuration fields carry their default, unit,
range and meaning (``core.settings``: ``NavigatorConfig``, ``FollowerConfig``), and so do the
node's own (`DpnParameters`, ``safety_params.SafetyParameters``). `PARAMETERS` lists the ROS
parameters in order, each with where its value goes; the node declares them from it, and
``config/dpn.yaml`` and the table of ``docs/ros_reference.md`` are written from it
(``tools/parameter_files.py``; a test fails when either differs). The defaults are the Husky
on back_and_forth, task 0: the core's, but for the map size, its growth, the laser mount and
the goal. The node turns the values into the core's frozen ``NavigatorConfig`` and never passes
itself into the core. Number parameters take integers too (``-p map_width:=25``).

"""

from dataclasses import dataclass
import math

from .parameter_declaration import declare_setting
from .safety_params import SafetyParameters
from ..core import FollowerConfig, GridGeometry, NavigatorConfig
from ..core.cell_label import OCCUPANCY_MOBILE_OBSTACLE
from ..core.mapping.map_growth import MAX_MAP_CELLS
from ..core.settings import Setting, setting, settings_of

#: Most grid cells a node may ask for (2048 x 2048): the grid and A*'s arrays stay in memory and
#: one plan in seconds. More is a parameter error, not a MemoryError in numpy; a map that grows
#: stops there too.
MAX_GRID_CELLS = MAX_MAP_CELLS
#: Largest fine free-evidence grid (2 bytes a cell: 134 MB; 819 m x 819 m at 0.1 m).
MAX_FINE_GRID_CELLS = 8192 * 8192


@dataclass(frozen=True)
class DpnParameters:
    """
    The node's parameters, read once at start-up.

    The node's own fields carry their unit, range and meaning as settings.

    Attributes
    ----------
    navigator : NavigatorConfig
        The core's configuration.
    centre_on_start : bool
        ``origin_x``/``origin_y`` are NaN: the map is to be centred on the robot's pose at its
        first scan (``navigator.origin`` is a placeholder until then).
    goal : (float, float) or None
        The goal in the map frame [m] given by ``goal_x``/``goal_y`` with ``use_default_goal``;
        None: wait for one on ``goal_pose`` (or the ``navigate_to_pose`` action).

    """

    navigator: NavigatorConfig
    goal: tuple
    centre_on_start: bool
    sensor_timeout: float = setting(
        0.4, 's', 'stop the robot when scan or odometry is older, on the node clock or the '
        'steady clock ([safety](safety.md))', 0.01, 60.0)
    map_publish_period: float = setting(
        0.0, 's', 'publish the map at most this often; 0: every scan', 0.0, 60.0)
    marker_min_period: float = setting(
        0.2, 's', 'send the markers and plan at most this often on replans and status changes '
        '(a later one waits for the period); 0: on every one; they also go out every 0.5 s',
        0.0, 60.0)
    map_frame: str = setting(
        'map', '', 'frame of the map, the plan and the markers; goals in another frame are '
        'rejected (an empty goal frame means this one)')
    laser_frame: str = setting(
        'laser', '', 'frame the scans must be in (`laser_x`/`_y`/`_yaw` place it on the base); '
        "scans in another frame are rejected and counted; '': any")
    base_frame: str = setting(
        'base_link', '', 'frame of the robot base: its map pose from TF (`map_frame -> '
        'base_frame`); header of TwistStamped commands')
    odom_frame: str = setting(
        'odom', '', 'frame of the odometry (REP 105); odometry in another frame is warned about '
        "once; '': any")
    pose_source: str = setting(
        'auto', '', 'where scans are placed from: `tf` (`map_frame -> <scan frame>` at the '
        "scan's stamp, the full 3-D mount), `odom` (the odometry pose taken as the map pose, "
        'the laser at `laser_x`/`_y`/`_yaw`), `auto` (`tf` once TF links `map_frame` to the '
        'scan frame, `odom` until then)')
    pose_source_wait: float = setting(
        1.0, 's', 'with `pose_source: auto`, how long (by scan stamps, from the first scan) '
        'scans wait for TF before odometry and the `laser_*` mount are used; a scan of that '
        'wait is dropped and counted if TF does not come within `transform_timeout`', 0.0,
        60.0)
    transform_timeout: float = setting(
        0.2, 's', "longest wait (steady clock) for a scan's transform or bracketing odometry; "
        'then the scan is dropped and counted', 0.0, 10.0)
    max_pose_gap: float = setting(
        0.15, 's', "longest time between the two samples of the robot's motion (TF "
        "`base_frame` in its parent, or two odometry messages) a scan's pose is interpolated "
        'across while the robot moves; a scan beyond it is dropped and counted (lost messages '
        'under load; a turn that starts inside the gap misplaces far hits); 0: no limit; not '
        'checked with tf2_ros', 0.0, 10.0)
    max_laser_tilt: float = setting(
        0.05, 'rad', 'largest tilt of the laser (from TF) from level or upside down; a more '
        'tilted scan is dropped and counted', 0.0, 0.5)
    max_linear_accel: float = setting(
        2.5, 'm/s^2', 'largest growth of the forward speed command (slowing down is not '
        "limited; Nav2's velocity_smoother default); 0: no limit", 0.0, 100.0)
    max_angular_accel: float = setting(
        3.2, 'rad/s^2', 'largest growth of the turn rate command; 0: no limit', 0.0, 100.0)
    cmd_vel_stamped: bool = setting(
        False, '', "send geometry_msgs/TwistStamped on cmd_vel instead of Twist (Jazzy's "
        'diff_drive_controller takes TwistStamped)')
    map_mobile_value: int = setting(
        OCCUPANCY_MOBILE_OBSTACLE, '', 'OccupancyGrid value of mobile-obstacle cells in `map` '
        '(steady obstacles are 100)', 1, 100)
    autostart: bool = setting(
        True, '', 'configure and activate the (lifecycle) node at start; false: wait for '
        '`change_state` calls, e.g. from nav2_lifecycle_manager (set its `bond_timeout: 0.0`)')
    use_default_goal: bool = setting(
        False, '', 'start with the goal `goal_x`, `goal_y`; false: no goal (and no motion) until '
        'one arrives on `goal_pose`')
    map_updates: bool = setting(
        True, '', 'between full maps (`map_publish_period` > 0), publish the box of cells '
        'changed since the last map or update on `map_updates` (map_msgs/OccupancyGridUpdate); '
        'false: nothing between full maps')


@dataclass(frozen=True)
class RosParameter:
    """
    One ROS parameter of the ``dpn`` node and where its value goes.

    Attributes
    ----------
    name : str
        The ROS name.
    default : float or int or bool or str
        Its default.
    setting : Setting
        Unit, range and meaning.
    target : str
        ``'navigator'`` (a ``NavigatorConfig`` field), ``'follower'`` (``FollowerConfig``),
        ``'node'`` (`DpnParameters`) or ``'safety'`` (``SafetyParameters``, declared by
        ``safety_params``).
    field : str
        The field of ``target`` it sets.
    index : int or None
        The component of a tuple field (``origin``, ``laser_offset``, ``goal``) it sets.

    """

    name: str
    default: object
    setting: Setting
    target: str
    field: str
    index: object = None


_CONFIGS = {'navigator': NavigatorConfig, 'follower': FollowerConfig, 'node': DpnParameters,
            'safety': SafetyParameters}


def _field(target, name, ros_name=None, default=None):
    """Return the `RosParameter` of a field with a setting; ``default`` overrides its own."""
    field_default, field_setting = settings_of(_CONFIGS[target])[name]
    return RosParameter(ros_name or name, field_default if default is None else default,
                        field_setting, target, name)


def _part(name, default, unit, description, low, high, target, field_name, index):
    """Return the `RosParameter` of a component of a tuple field, whose setting is here."""
    return RosParameter(name, default, Setting(unit, description, low, high), target,
                        field_name, index)


def _navigator(*names):
    return tuple(_field('navigator', name) for name in names)


#: Every parameter of the dpn node, in the order of ``config/dpn.yaml`` and of the reference
#: table. The defaults the core lacks or that differ from it: the map size, the laser mount
#: and the goal of the Husky on back_and_forth.
PARAMETERS = (
    _field('navigator', 'width', 'map_width', 25.0),
    _field('navigator', 'height', 'map_height', 20.0),
    _part('origin_x', 0.0, 'm', "map-frame x of the environment's lower-left corner; NaN (with "
          '`origin_y`): the map centred on where the robot is at its first scan', None, None,
          'navigator', 'origin', 0),
    _part('origin_y', 0.0, 'm', "map-frame y of the environment's lower-left corner; NaN: see "
          '`origin_x`', None, None, 'navigator', 'origin', 1),
    _field('navigator', 'resolution'),
    _field('navigator', 'safety_radius', 'robot_radius'),
    *_navigator('footprint_radius', 'obstacle_proximity_cost',
                'forget_obstacles_after', 'free_evidence_radius', 'moving_object_size',
                'evidence_margin', 'segment_gap', 'segment_bridge_beams', 'object_min_hits',
                'fine_evidence_resolution', 'fine_evidence_radius', 'fine_evidence_range'),
    # A localiser's pose carries a heading error: the fine evidence is renewed every 3 m of
    # travel (the core's default, 0, keeps it for good: the benchmark's pose is exact).
    _field('navigator', 'free_evidence_renewal', default=6.0),
    *_navigator('mobile_expiry', 'track_confirm_time', 'track_still_distance',
                'track_exclusive', 'trail_distance', 'object_memory',
                'object_memory_short_segments', 'no_echo_below_range_min',
                'no_return_reach', 'no_return_standing_distance', 'no_return_standing_time',
                'surface_time', 'surface_memory', 'noise_margin',
                'mixed_pixel_angle', 'spike_angle', 'edge_pixel_flatness', 'veiling_angle',
                'range_noise_margin',
                'range_noise_fraction', 'free_burn_in', 'free_first_sight',
                'object_min_width',
                'robot_length', 'robot_width',
                'turn_sweep_memory', 'turn_sweep_margin', 'turn_sweep_spot_distance',
                'drive_guard_distance'),
    *_navigator('stale_obstacle_age', 'path_trust_time', 'route_block_distance',
                'route_switch_margin', 'route_review_period', 'route_review_margin',
                'route_block_memory',
                'mobile_wait_time', 'give_way_time',
                'give_way_distance', 'give_way_hold', 'unknown_cell_cost',
                'forgotten_obstacle_cost', 'wall_continuation_angle', 'wall_continuation_reach',
                'wall_continuation_cost', 'real_laser_switch'),
    # The map grows in blocks of 5 m (the core's default, 0, keeps it fixed as the paper).
    _field('navigator', 'map_growth_step', default=5.0),
    *_navigator('map_growth_margin', 'map_memory_limit'),
    _field('node', 'autostart'),
    _field('node', 'use_default_goal'),
    _part('goal_x', 2.0, 'm', 'goal x in the map frame (back_and_forth, task 0), used only with '
          '`use_default_goal`; NaN: wait for a goal on `goal_pose`', None, None, 'node', 'goal',
          0),
    _part('goal_y', 18.0, 'm', 'goal y in the map frame, used only with `use_default_goal`; '
          'NaN: wait for a goal on `goal_pose`', None, None, 'node', 'goal', 1),
    _field('follower', 'max_linear_speed', 'max_vel_x'),
    _field('follower', 'max_angular_speed', 'max_vel_theta'),
    _field('follower', 'goal_tolerance', 'xy_goal_tolerance'),
    # A real robot's pose carries its localiser's error: it stops 0.1 m inside the tolerance
    # (the core's default, 0, stops at the tolerance's edge as the paper).
    _field('follower', 'goal_approach_margin', default=0.1),
    *(_field('follower', name) for name in ('lookahead_distance',
                                            'heading_gain', 'turn_in_place_angle',
                                            'slowdown_distance', 'corner_angle')),
    _field('navigator', 'max_path_deviation'),
    _field('node', 'max_linear_accel'),
    _field('node', 'max_angular_accel'),
    _part('laser_x', 0.337, 'm', "laser position on the base, forward (the Husky's LMS1xx)",
          -10.0, 10.0, 'navigator', 'laser_offset', 0),
    _part('laser_y', 0.0, 'm', 'laser position on the base, left', -10.0, 10.0, 'navigator',
          'laser_offset', 1),
    _part('laser_yaw', 0.0, 'rad', 'laser heading on the base', -math.pi, math.pi,
          'navigator', 'laser_offset', 2),
    _field('node', 'sensor_timeout'),
    _field('safety', 'max_beams'),
    *(_field('node', name) for name in ('map_publish_period', 'map_updates',
                                        'marker_min_period', 'map_frame', 'laser_frame',
                                        'base_frame', 'odom_frame', 'pose_source',
                                        'pose_source_wait', 'transform_timeout',
                                        'max_pose_gap', 'max_laser_tilt', 'cmd_vel_stamped',
                                        'map_mobile_value')),
)


#: The names these parameters had before they took Nav2's (robot_radius in the costmaps,
#: max_vel_x and max_vel_theta in the controllers and the velocity smoother, xy_goal_tolerance
#: in the goal checker): still read for one release, with a deprecation warning.
DEPRECATED_ALIASES = {'safety_radius': 'robot_radius', 'max_linear_speed': 'max_vel_x',
                      'max_angular_speed': 'max_vel_theta', 'goal_tolerance': 'xy_goal_tolerance'}


def declare_parameter(node, parameter):
    """Declare one `RosParameter` on ``node`` (``declare_setting``); return its value."""
    return declare_setting(node, parameter.name, parameter.default, parameter.setting)


def declare_parameters(node):
    """
    Declare every parameter of the ``dpn`` node but the input limits, and read them.

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
    values = {}
    for parameter in PARAMETERS:
        if parameter.target != 'safety':
            values[parameter.name] = declare_parameter(node, parameter)
    values.update(read_deprecated_aliases(node, values))
    check_grid_size(values['map_width'], values['map_height'], values['resolution'])
    if values['fine_evidence_resolution'] > 0.0:
        check_grid_size(values['map_width'], values['map_height'],
                        values['fine_evidence_resolution'], MAX_FINE_GRID_CELLS,
                        'fine_evidence_resolution')
    fields_of = {'navigator': {}, 'follower': {}, 'node': {}}
    parts = {}
    for parameter in PARAMETERS:
        if parameter.target == 'safety':
            continue
        if parameter.index is None:
            fields_of[parameter.target][parameter.field] = values[parameter.name]
        else:
            parts.setdefault((parameter.target, parameter.field), {})[parameter.index] = \
                values[parameter.name]
    for (target, name), components in parts.items():
        fields_of[target][name] = tuple(components[k] for k in sorted(components))
    origin = fields_of['navigator']['origin']
    centre_on_start = any(math.isnan(v) for v in origin)
    if centre_on_start:
        if not all(math.isnan(v) for v in origin):
            raise ValueError('origin_x and origin_y: give both, or both NaN (the map centred on '
                             f'the start pose); got {origin}')
        # A placeholder until the first scan's pose places the map (DpnNode).
        fields_of['navigator']['origin'] = (-0.5 * values['map_width'],
                                            -0.5 * values['map_height'])
    fields_of['node']['centre_on_start'] = centre_on_start
    goal = fields_of['node'].pop('goal')
    if not (fields_of['node']['use_default_goal']
            and all(math.isfinite(value) for value in goal)):
        goal = None
    navigator = NavigatorConfig(**fields_of['navigator'],
                                follower=FollowerConfig(**fields_of['follower']))
    return DpnParameters(navigator, goal, **fields_of['node'])


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


def read_deprecated_aliases(node, values):
    """
    Declare the deprecated names of `DEPRECATED_ALIASES`; return the values they override.

    A deprecated name set to something other than its default is used (with a warning) unless
    the Nav2 name is also set, which then wins (with a warning naming both).

    Returns
    -------
    dict
        ``{nav2 name: value}`` of the deprecated names that were set.

    """
    by_name = {p.name: p for p in PARAMETERS}
    taken = {}
    for old, new in DEPRECATED_ALIASES.items():
        parameter = by_name[new]
        alias = RosParameter(old, parameter.default, Setting(
            parameter.setting.unit, f'deprecated: use {new}', parameter.setting.low,
            parameter.setting.high), parameter.target, parameter.field, parameter.index)
        value = declare_parameter(node, alias)
        if value == parameter.default:
            continue
        if values[new] != parameter.default:
            node.get_logger().warning(
                f'parameters {old} (deprecated) and {new} both set: using {new} = {values[new]}')
            continue
        node.get_logger().warning(
            f"parameter {old} is deprecated and will be removed: use {new} (Nav2's name); "
            f'taking {old} = {value}')
        taken[new] = value
    return taken
