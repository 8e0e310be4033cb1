"""
The dynamic planner navigator without ROS: grid update, replanning and path following per scan.

Per scan the navigator folds the scan into its ``LabelGrid``, decides whether to replan (the
grid's replan flag, no path yet, a blocked cell ahead on the path, the robot off its path, or a
new goal), plans with A* on the partly known grid (non-explored counts as free) and turns the
path into a velocity command. The ROS node and the batch benchmark both drive this object.
Issue 31's parts (stale obstacles, the honest no-path timer, route commitment and waiting,
exploration with memory; ``docs/method.md#not-getting-stuck``) hook in here, each in a module
of its own, each off with its setting at 0.

"""

from dataclasses import dataclass, field, fields, MISSING, replace
import enum
import math
import time

import numpy as np

from .cell_label import blocked_mask
from .control.drive_guard import DriveGuard
from .control.path_follower import follow_path, FollowerConfig, STOP, VelocityCommand
from .control.turn_sweep import TurnSweep
from .mapping.label_grid import LabelGrid, LabelRule, warm_up_label_update
from .mapping.map_growth import growth_to_cover, MAX_MAP_CELLS, scan_hit_box, scan_reach
from .mapping.scan_reading import read_no_echo
from .mapping.stale_obstacles import ObstacleConfirmations
from .mapping.surface_memory import MAX_CELLS as MAX_SURFACE_CELLS
from .mapping.wall_continuation import continued_walls, warm_up_wall_continuation
from .planning.astar_search import warm_up_astar
from .planning.exploration_memory import ExplorationMemory
from .planning.give_way import FACE_TOLERANCE, GiveWay
from .planning.planning_masks import PlanningMasks, touches_blocked  # noqa: F401 (re-exported)
from .planning.planning_masks import warm_up_planning_masks
from .planning.route_commitment import RouteCommitment
from .pose2d import compose
from .real_laser import real_laser_switch_for, take_real_laser_settings
from .scan_polygon import check_pose, scan_points
from .settings import BIG, setting


#: Forgetting unseen obstacles keeps those within this many safety radii of the robot.
FORGET_KEEP_RADII = 2.0

#: Extra A* cost of a stale cell in the search for the stale cells that close the route
#: [cells], plus one per scan that hit it: that search crosses as few of them as it can, and
#: the least often seen.
STALE_CELL_COST = 20.0


class NavigatorStatus(enum.Enum):
    """What the navigator is doing."""

    IDLE = 'idle'                    # no goal
    ACTIVE = 'active'                # following a path to the goal
    GOAL_REACHED = 'goal_reached'    # inside the goal tolerance; stays until a new goal
    NO_PATH = 'no_path'              # no path on the current map; retried as the map changes


class ReplanCause(enum.Enum):
    """Why a step planned a path."""

    NONE = ''                        # no planning in this step
    FLAG = 'flag'                    # the grid's replan flag: a path cell turned obstacle
    NO_PATH_RETRY = 'no_path_retry'  # a retry while there was no path
    OTHER = 'other'                  # no path yet (new goal), a blocked cell ahead, off the path


@dataclass(frozen=True)
class NavigatorConfig:
    """
    Everything the navigator needs to know before the first scan.

    The fields declared with ``setting`` carry their unit, range and meaning on the field
    (``settings.settings_of(NavigatorConfig)``): the ``dpn`` node declares its parameters from
    them, and ``docs/ros_reference.md`` lists them. The label fields go to the grid's
    ``LabelRule`` under the same names (``label_rule``), whose docstring says how each rule
    works. The others:

    Attributes
    ----------
    origin : (float, float)
        Map-frame position of the environment's lower-left corner [m].
    laser_offset : (float, float, float)
        Laser pose on the robot base ``(x, y, yaw)`` [m, m, rad].
    max_path_deviation : float
        Replan when the robot is farther than this from its path [m].
    no_path_retry_period : float
        While there is no path, plan again at most this often [s].
    follower : FollowerConfig
        Speed limits and gains of the path follower.

    """

    width: float = setting(MISSING, 'm', 'width W of the environment along x', 0.1, BIG)
    height: float = setting(MISSING, 'm', 'height H of the environment along y', 0.1, BIG)
    origin: tuple = (0.0, 0.0)
    resolution: float = setting(0.5, 'm', 'grid cell side (the paper: 0.5)', 0.01, 10.0)
    safety_radius: float = setting(
        0.6, 'm', "f1's r: cells this close to a laser hit are obstacles (the Husky's "
        'circumscribed radius)', 0.0, 5.0)
    footprint_radius: float = setting(
        0.35, 'm', 'cells this close to the robot are planned through even when labelled '
        'obstacles: the robot stands on them, so what was seen there has moved', 0.0, 2.0)
    laser_offset: tuple = (0.0, 0.0, 0.0)
    max_path_deviation: float = setting(
        1.0, 'm', 'replan when the robot is farther than this from its path', 0.01, 100.0)
    obstacle_proximity_cost: float = setting(
        1.0, 'cells', 'extra A\\* cost of a free cell next to an obstacle (8-neighbourhood): '
        "paths keep a cell off walls where there is room, so that the Husky's corners clear "
        'them; 0: plain shortest paths (the paper)', 0.0, 100.0)
    no_path_retry_period: float = 0.5
    forget_obstacles_after: float = setting(
        10.0, 's', 'with no path this long, forget the mobile cells out of view (back to '
        'explored) and plan again; as long again with still no path, every obstacle cell out '
        'of view goes back to non-explored; cells within 1.2 m of the robot are kept; 0: '
        'never (the paper)', 0.0, 3600.0)
    free_evidence_radius: float = setting(
        0.6, 'm', 'conservative free space: explored -> mobile only for cells whose disc of '
        'this radius once lay inside one scan polygon, else steady; 0: the paper '
        '([detection](detection.md))', 0.0, 5.0)
    moving_object_size: float = setting(
        0.7, 'm', 'object-level relabelling: hit cells near a scan segment seen to move are '
        'mobile, other hit cells steady; 0: off', 0.0, 10.0)
    evidence_margin: float = setting(
        0.15, 'm', 'a hit shows motion only within `free_evidence_radius` minus this of a '
        'cell surely seen free', 0.0, 5.0)
    segment_gap: float = setting(
        0.3, 'm', 'consecutive laser hits farther apart than this are different objects',
        0.01, 10.0)
    segment_bridge_beams: int = setting(
        2, 'beams', 'lost returns inside a surface: a scan segment goes on across up to this '
        'many consecutive beams without a hit when the hits on both sides lie within '
        '`segment_gap` (a real laser loses 0.5-2 % of its returns, and the pieces of a wall '
        'between them stand free: next to a walker they continue its track; with the '
        'simulated UTM-30LX, 2 takes the walls ever mobile from 1.1-1.7 to 0.2-0.3 %, and the '
        'episodes with the ideal laser are identical: '
        '[method](method.md#the-dpn-label-rules-not-in-the-paper)); 0: every beam without a '
        'hit ends a segment (the paper)', 0, 1_000_000)
    object_min_hits: int = setting(
        3, 'hits', 'thin things: a free-standing scan segment of fewer hits shows no motion, '
        'starts and continues no motion track and is not remembered as a place an object '
        'stood (a post thinner than about two beam spacings slips between the beams, so its '
        'next hit looks like motion); 0: off (the paper)', 0, 1_000_000)
    fine_evidence_resolution: float = setting(
        0.1, 'm', 'fine free evidence: a laser hit also shows motion when its cell of a grid '
        'this fine was once surely seen free (its disc of `fine_evidence_radius` inside one '
        'scan polygon); 0 (with the radius 0): off, the paper; the fine grid covers the map '
        'and may hold at most 8192 x 8192 cells (2 bytes each), else the node refuses to '
        'start', 0.0, 5.0)
    fine_evidence_radius: float = setting(
        0.2, 'm', 'fine free evidence: a fine cell is surely free when its disc of this '
        'radius lay inside one scan polygon; 0: off', 0.0, 5.0)
    fine_evidence_range: float = setting(
        20.0, 'm', 'fine free evidence: fine cells are marked surely free only within this '
        'distance of the laser (640 beams over 180 degrees are 9.8 cm apart at 20 m, under a '
        'fine cell; farther, a thin thing hides between two beams)', 0.01, 1000.0)
    free_evidence_renewal: float = setting(
        0.0, 'm', 'free evidence (conservative and fine) older than this much travel of the '
        'laser is dropped (two generations, one begun every half of it), so that the heading '
        'error of a localiser, which shifts what two poses d metres apart see by that angle '
        'times d, shows no wall moving; 0: kept for good (the core and the benchmark, whose '
        'pose is exact)', 0.0, 1000.0)
    mobile_expiry: float = setting(
        3.0, 's', 'mobile cells that no hit confirmed for this long and that are out of view '
        'go back to explored; 0: never (the paper)', 0.0, 3600.0)
    track_confirm_time: float = setting(
        5.0, 's', 'motion tracks: a compact, free-standing scan segment near an object seen '
        'to move is that object, mobile, while motion was seen within this long; 0: off '
        '([method](method.md#the-dpn-label-rules-not-in-the-paper))', 0.0, 3600.0)
    track_still_distance: float = setting(
        0.08, 'm', 'still objects: a compact scan segment this close to where a compact '
        'free-standing one stood 0.8-1.5 s ago stood still: the places left empty near it '
        '(by a wanderer passing a post) do not show it moving, and it does not continue a '
        'track that never moved 0.3 m; 0: off '
        '([method](method.md#the-dpn-label-rules-not-in-the-paper))', 0.0, 10.0)
    track_exclusive: bool = setting(
        True, '', 'exclusive tracks: at most one scan segment continues a track per scan '
        '(false: segments share one, as a post next to a wanderer did)')
    trail_distance: float = setting(
        1.2, 'm', 'trails: mobile cells out of view whose followed object the scan sees at '
        'least this far from them go back to explored; 0: off', 0.0, 100.0)
    object_memory: float = setting(
        5.0, 's', 'object memory: steady cells of small objects (scan segments up to 1 m with '
        '3 hits or more) that no longer segment has hit are forgotten (explored if once '
        'surely seen free, else non-explored) after this long with no hit, out of view and '
        'more than 2 safety radii from the laser; 0: off', 0.0, 3600.0)
    object_memory_short_segments: bool = setting(
        True, '', 'short segments in the object memory: steady cells that only laser segments '
        'of one or two hits have hit (a wanderer glimpsed far off through a gap) are listed '
        'and forgotten as `object_memory` forgets small objects, unless a longer segment '
        'anchors them; false: kept (read only with `object_memory` > 0)')
    no_echo_below_range_min: bool = setting(
        False, '', 'no-echo codes: a finite reading below range_min is read as no return '
        '(+inf), not as invalid (REP 117), for drivers that write a beam with no echo as a '
        'tiny range (the old Hokuyo driver: 0.000-0.019 m; [real data](real_data.md))')
    no_return_reach: float = setting(
        0.8, '1', 'a beam with no return shows space empty out to this share of range_max '
        '(weak echoes of dark or far surfaces drop out before range_max); 1: to range_max '
        "(the paper, REP 117; Nav2's inf_is_valid true); 0: it clears nothing (inf_is_valid "
        'false)', 0.0, 1.0)
    no_return_standing_distance: float = setting(
        0.0, 'm', 'beams with no return clear (out to `no_return_reach`) only while the laser '
        'stands, within this distance of one place for `no_return_standing_time`; while it '
        'moves they clear nothing, and when it starts to move the free evidence is dropped '
        '(a wall at grazing incidence returns nothing, and turns towards a moving laser: its '
        'echo would land in space shown empty; [real data](real_data.md)); 0: off, '
        '`no_return_reach` always', 0.0, 10.0)
    no_return_standing_time: float = setting(
        0.5, 's', 'how long the laser must stay within `no_return_standing_distance` of a '
        'place before it stands (read only with `no_return_standing_distance` > 0)',
        0.0, 3600.0)
    surface_time: float = setting(
        2.0, 's', 'intermittent surfaces: a place (a cell of `noise_margin`) hit for this '
        'long in all is a known surface; hits within one place of it show no motion and '
        'continue no motion track (longer than a leg stands at walking pace, about 0.6 s, '
        'or a walker or robot pauses briefly; 1 s: more precision on real recordings, less '
        'recall in the simulator, [real data](real_data.md)); 0: off (the paper)', 0.0, 3600.0)
    surface_memory: float = setting(
        10.0, 's', "intermittent surfaces: a place's hit time drains by `surface_time` in this "
        'long', 0.001, 86400.0)
    noise_margin: float = setting(
        0.1, 'm', 'intermittent surfaces: side of a place, about the range noise of the '
        'laser (Hokuyo UTM-30LX and SICK LMS1xx: +-30 mm)', 0.01, 5.0)
    mixed_pixel_angle: float = setting(
        0.0, 'rad', 'mixed pixels: a hit between its two neighbours in depth, the segments to '
        'both within this angle of its beam, is read as invalid (a spot that fell on both '
        "sides of a depth edge; 0.17 rad = 10 deg, as laser_filters' shadow filter); 0: off "
        '(the paper)', 0.0, 1.5707963267948966)
    spike_angle: float = setting(
        0.0, 'rad', 'spikes: a hit whose two neighbours both lie nearer, or both farther, the '
        'segments to both within this angle of its beam, is read as invalid (two mixed pixels '
        "side by side at a depth edge, speckle, a thing one beam wide; laser_filters' speckle "
        'filter drops them by range difference); 0: off (the paper)', 0.0, 1.5707963267948966)
    edge_pixel_flatness: float = setting(
        0.0, 'm', 'flat walls at grazing incidence: a hit within this distance, along its beam, '
        "of the line through its neighbours' points is on a flat surface with them, neither a "
        'mixed pixel nor a spike (a wall met more than 90 deg - `mixed_pixel_angle` from its '
        'normal looks like one); 0: off ([method](method.md#the-dpn-label-rules-not-in-the-'
        'paper))',
        0.0, 1.0)
    veiling_angle: float = setting(
        0.0, 'rad', "veiling hits (laser_filters' shadow filter): a hit whose segment to a "
        'neighbour lies within this angle of its beam (beside a depth edge, or on a surface '
        'at grazing incidence) shows no motion of its own, and still marks its cells; 0: off '
        '(the paper); needs surface_time > 0', 0.0, 1.5707963267948966)
    range_noise_margin: float = setting(
        0.0, 'm', 'range noise: a hit shows motion of its own only when the point this much '
        '(plus `range_noise_fraction` of its range) farther along its beam does too, so that '
        'a short reading of a surface a long one showed empty is not motion; about three '
        "standard deviations of the laser's range noise; 0: off (the paper); needs "
        'surface_time > 0', 0.0, 1.0)
    range_noise_fraction: float = setting(
        0.0, '1', 'range noise: the part of `range_noise_margin` that grows with the range, '
        'for a laser whose noise is a share of the distance, or a heading error (0.015: three '
        "sigma of an RPLIDAR A2's 0.5 %; 0.03: of a 0.01 rad heading error); 0: off (the "
        'paper)', 0.0, 0.2)
    free_burn_in: float = setting(
        0.0, 's', "burn-in of the fine free evidence (Dynablox's burn_in_period): a fine cell "
        'counts as surely seen empty only when no hit has come within fine_evidence_radius '
        'of it for this long, so that a surface that returns an echo in some scans only does '
        'not look like motion; 0: off (the paper); needs the fine free evidence', 0.0, 60.0)
    free_first_sight: float = setting(
        0.0, 's', 'free evidence needs a second look: a cell (label or fine) counts as surely '
        'seen empty only from a scan at least this long after the first scan that showed it '
        'empty, so '
        "that a surface that gave no echo in the first scan to see it (a recording's first) "
        'does not look like motion when it echoes; 0: off (the paper); needs the fine free '
        'evidence', 0.0, 10.0)
    object_min_width: float = setting(
        0.0, 'm', 'narrow things: a scan segment whose end hits lie less than this apart '
        'shows no motion of its own (a leg is 0.1-0.15 m wide; a cable, chair leg or spot of '
        'a dark surface a few centimetres wide is not a moving object); 0: off (the paper); '
        'needs surface_time > 0', 0.0, 1.0)
    robot_length: float = setting(
        0.99, 'm', "the robot's footprint along x, centred on the base (Husky A200 with "
        'bumpers); used by the turn sweep', 0.01, 10.0)
    robot_width: float = setting(
        0.67, 'm', "the robot's footprint along y, centred on the base", 0.01, 10.0)
    turn_sweep_memory: float = setting(
        2.0, 's', 'turn sweep: a turn in place is tested against the laser hits kept around '
        'the robot (while in reach and not seen through); a hit counts this long, then while '
        "the grid labels its cell an obstacle; when the robot's corners would hit one, it "
        'moves to a nearby place the turn is clear from, else waits; 0: off (the paper; '
        '[safety](safety.md#turning-in-place))', 0.0, 60.0)
    turn_sweep_margin: float = setting(
        0.05, 'm', 'clearance the turn sweep keeps from those hits', 0.0, 1.0)
    turn_sweep_spot_distance: float = setting(
        0.6, 'm', 'farthest place the turn sweep moves the robot to for a blocked turn; 0: it '
        'waits', 0.0, 5.0)
    drive_guard_distance: float = setting(
        0.3, 'm', "drive guard: a forward command's arc is followed this far and tested against "
        "the turn sweep's kept hits (so it needs `turn_sweep_memory` > 0); when the robot's box "
        'would touch one (with `turn_sweep_margin`), the robot steers slowly along the nearest '
        'clear arc, else stops; 0: off (the paper; [safety](safety.md#driving-past-a-body))',
        0.0, 5.0)
    stale_obstacle_age: float = setting(
        6.0, 's', 'stale obstacles: with no path, the obstacle cells no laser hit has confirmed '
        'for this long that alone close the route (a path exists without them) are dropped '
        '(explored if once surely seen free, else non-explored) on the cheapest such path, and '
        'the robot drives to see them; a wall there is hit and marked again; 0: off (the '
        'paper; [method](method.md#not-getting-stuck))', 0.0, 3600.0)
    path_trust_time: float = setting(
        3.0, 's', 'honest no-path timer: a path found while there was none ends the no-path '
        'spell (and restarts the `forget_obstacles_after` timer) only once it has lasted this '
        'long; a plan the next scans take away at once does not; 0: any path ends it (the '
        'paper)', 0.0, 3600.0)
    route_block_distance: float = setting(
        4.0, 'm', 'route commitment: mobile cells farther than this from the robot are planned '
        'through (the object moves on before the robot gets there) and a new plan replaces '
        'the route only when cheaper by `route_switch_margin` or when the route is blocked; '
        '0: off (the paper)', 0.0, 1000.0)
    route_switch_margin: float = setting(
        3.0, 'm', 'route commitment: how much cheaper a new route must be to replace the '
        'current one (read only with `route_block_distance` > 0)', 0.0, 1000.0)
    route_review_period: float = setting(
        2.0, 's', 'route commitment: while a route is followed, plan again this often and take '
        'the new plan when it is cheaper by `route_review_margin` (a detour taken round a '
        'blocked corridor is left once the corridor opens again; the paper plans again only '
        'when a cell of the path turns obstacle); 0: off (the paper; read only with '
        '`route_block_distance` > 0)', 0.0, 3600.0)
    route_review_margin: float = setting(
        10.0, 'm', 'route commitment: how much cheaper a plan found by `route_review_period` '
        'must be to replace the route (at least `route_switch_margin`)', 0.0, 1000.0)
    route_block_memory: float = setting(
        0.0, 's', 'route commitment: a route left because a cell of it was blocked is not taken '
        'back for this long: a new plan through a cell that blocked a route within this time '
        'does not replace an open route (a cell beside a standing agent flickers between mobile '
        'and free); 0: off (the default and the paper: 3 s lost 8 goals on the held-out seed, '
        '[method](method.md#not-getting-stuck); read only with `route_block_distance` > 0)',
        0.0, 3600.0)
    mobile_wait_time: float = setting(
        5.0, 's', 'waiting: a mobile blob within `route_block_distance` is planned through at '
        'the cost of driving this long plus the time already waited for it, and the robot '
        'stops 1 m before it; a detour is taken when it is shorter than waiting; mobile cells '
        'within 1 m of the robot block; 0: such cells block (read only with '
        '`route_block_distance` > 0)', 0.0, 3600.0)
    give_way_time: float = setting(
        30.0, 's', 'giving way: a robot that has stood still this long with mobile cells within '
        '4 safety radii (an agent that waits for it, as it waits for the agent) drives to the '
        'nearest place within `give_way_distance` from which the agent can pass it, waits '
        'there up to `give_way_hold` and goes on; 0: off (the paper; '
        '[method](method.md#giving-way))', 0.0, 3600.0)
    give_way_distance: float = setting(
        6.0, 'm', 'giving way: the farthest place, along the way there, the robot gives way '
        'from (read only with `give_way_time` > 0)', 0.5, 100.0)
    give_way_hold: float = setting(
        10.0, 's', 'giving way: the longest wait at the place, facing the agent (shorter once '
        "a path to the goal enters no agent's cell; read only with `give_way_time` > 0)",
        0.0, 3600.0)
    unknown_cell_cost: float = setting(
        1.0, 'cells', 'exploration: extra A\\* cost of entering a non-explored cell (NavFn '
        'plans through unknown space at 253 against 50 for free, about 4 cells); 0: unknown '
        'counts as free (the paper)', 0.0, 100.0)
    forgotten_obstacle_cost: float = setting(
        20.0, 'cells', 'exploration memory: extra A\\* cost of entering a non-explored cell '
        'once an obstacle (a forgotten wall of an explored dead end), instead of '
        '`unknown_cell_cost`: passable as a last resort; 0: off (the paper)', 0.0, 1000.0)
    wall_continuation_angle: float = setting(
        0.0, 'rad', 'walls that go on (for real lasers, which return nothing from a wall met '
        "at a grazing angle): when the beam of a wall's last hit next to beams with no return "
        "meets it at more than this from its normal, the non-explored cells along the wall's "
        'line, as far as those beams would meet it, cost `wall_continuation_cost` to enter; 0: '
        'off (the paper; [method](method.md#walls-that-go-on))', 0.0, 1.5)
    wall_continuation_reach: float = setting(
        8.0, 'm', 'walls that go on: the longest continuation past the last hit (read only with '
        '`wall_continuation_angle` > 0)', 0.5, 100.0)
    wall_continuation_cost: float = setting(
        100.0, 'cells', 'walls that go on: extra A\\* cost of entering a non-explored cell on a '
        "wall's continuation (instead of `unknown_cell_cost` or `forgotten_obstacle_cost` when "
        'larger; read only with `wall_continuation_angle` > 0)', 0.0, 10000.0)
    real_laser_switch: float = setting(
        0.001, '1', 'a real laser on the move: once the laser has moved more than 0.1 m and, '
        'over at least 3 scans, at least 5 and more than this share of the readings were '
        'returns lost inside a surface (runs of 1-2 beams without a valid reading between '
        'hits within 0.3 m of each other; an ideal laser loses none, real ones 0.2-1 %), the '
        'settings of '
        '`config/dpn_real_laser.yaml` left at their defaults are taken, once, and the map '
        'starts again from the next scan ([method](method.md#a-real-laser-on-the-move)); 0: '
        'off (the paper)', 0.0, 1.0)
    map_growth_step: float = setting(
        0.0, 'm', 'maps that grow: when the robot comes within `map_growth_margin` of an edge '
        'of the map, a laser hit falls beyond one, or a goal lies off the map, the map grows on '
        'that side by whole blocks of this size (rounded up to whole cells; its origin moves by '
        'whole cells, so every cell keeps its place), up to `map_memory_limit`; 0: the map '
        'stays as given (the paper)', 0.0, 1000.0)
    map_growth_margin: float = setting(
        2.0, 'm', 'maps that grow: the room the robot, and what a scan hits beyond the map, '
        'are given from the edge when the map grows', 0.0, 100.0)
    map_memory_limit: float = setting(
        512.0, 'MB', 'maps that grow: the map grows no further when its per-cell arrays (the '
        'labels and every memory kept per cell) would take more; the growth is refused, '
        'counted and logged', 1.0, 1e6)
    follower: FollowerConfig = field(default_factory=FollowerConfig)

    def __post_init__(self):
        for name in ('safety_radius', 'footprint_radius', 'no_path_retry_period',
                     'obstacle_proximity_cost', 'forget_obstacles_after', 'turn_sweep_memory',
                     'turn_sweep_margin', 'turn_sweep_spot_distance', 'drive_guard_distance',
                     'stale_obstacle_age',
                     'path_trust_time', 'route_block_distance', 'route_switch_margin',
                     'route_review_period', 'route_review_margin', 'route_block_memory',
                     'mobile_wait_time',
                     'give_way_time', 'give_way_distance',
                     'give_way_hold', 'unknown_cell_cost', 'forgotten_obstacle_cost',
                     'wall_continuation_angle', 'wall_continuation_cost', 'map_growth_step',
                     'map_growth_margin', 'map_memory_limit', 'real_laser_switch'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if not (math.isfinite(self.max_path_deviation) and self.max_path_deviation > 0.0):
            raise ValueError(
                f'max_path_deviation must be positive, got {self.max_path_deviation!r}')
        for name in ('robot_length', 'robot_width'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        if not self.wall_continuation_angle < 0.5 * math.pi:
            raise ValueError('wall_continuation_angle must be below pi / 2, got '
                             f'{self.wall_continuation_angle!r}')
        if not (math.isfinite(self.wall_continuation_reach)
                and self.wall_continuation_reach > 0.0):
            raise ValueError('wall_continuation_reach must be positive and finite, got '
                             f'{self.wall_continuation_reach!r}')
        check_pose(self.laser_offset, 'laser_offset')
        self.label_rule()                        # validates the label rule's fields

    def label_rule(self):
        """Return the grid's ``LabelRule`` from the label fields of this configuration."""
        return LabelRule(**{item.name: getattr(self, item.name) for item in fields(LabelRule)})


@dataclass(frozen=True)
class NavigatorOutput:
    """
    The result of one navigator step.

    Attributes
    ----------
    command : VelocityCommand
        What to send to the base.
    status : NavigatorStatus
    reason : str
        Why the status is what it is, for people (empty when active).
    replanned : bool
        True when this step computed a new path.
    replan_cause : ReplanCause
        Why it did (``ReplanCause.NONE`` when it did not); the flag wins over a stale path.

    """

    command: VelocityCommand
    status: NavigatorStatus
    reason: str = ''
    replanned: bool = False
    replan_cause: ReplanCause = ReplanCause.NONE


class Navigator:
    """
    Map, plan and follow toward a goal in an unknown environment with moving obstacles.

    Parameters
    ----------
    config : NavigatorConfig
    grid : PlanningMap, optional
        The map to plan on, in place of the ``LabelGrid`` built from ``config``: any
        ``mapping.label_grid.PlanningMap`` (the interface the navigator relies on; the
        benchmark's reference navigators plan on its ``CostmapGrid`` and ``OracleGrid``).

    Attributes
    ----------
    grid : PlanningMap
        The map planned on: the labelled occupancy grid built from the scans by default.
    path : (N, 2) ndarray of int64, or None
        The planned path as ``(row, col)`` cells, start to goal.
    goal : (float, float) or None
        The goal in the map frame [m].
    status : NavigatorStatus
    replans : int
        How many paths have been planned since the goal was set.
    forgets : int
        How many times unseen obstacles were forgotten since the goal was set (see
        ``NavigatorConfig.forget_obstacles_after``).
    stale_drops : int
        How many times stale obstacle cells that alone closed the route were dropped since
        the goal was set (``NavigatorConfig.stale_obstacle_age``).
    commitment : RouteCommitment or None
        The route commitment and the wait (``route_block_distance``); None when off.
    route_reviews : int
        How many times a route review (``route_review_period``) replaced the route since the
        goal was set (each also counts in ``replans``).
    map_growths, map_growth_refusals : int
        How often the map grew (``map_growth_step``), and how many distinct growths it needed
        were refused (``map_memory_limit``, the cell limit, or a map that cannot grow); the
        same growth asked for again (by every scan of a robot at the edge) counts once.
    map_growth_refusal : str
        Why the last growth was refused ('' before any).
    real_laser : RealLaserSwitch or None
        What tells a real laser on the move (``real_laser_switch``); None when off, on a grid
        other than the ``LabelGrid``, or when the settings already are the real laser's.
    real_laser_settings : dict of str to float
        The settings the switch took (empty until it switched).
    real_laser_since : float or None
        The stamp given to `observe` with the first scan read with them [s]: the scan after
        the one that showed the real laser (None before, or when that scan had none).

    """

    def __init__(self, config, grid=None):
        self.config = config
        self.grid = grid if grid is not None else LabelGrid(
            config.width, config.height, config.resolution, config.origin, config.label_rule())
        self._masks = PlanningMasks(self.grid, config.obstacle_proximity_cost)
        self.path = None
        self.goal = None
        self.status = NavigatorStatus.IDLE
        self.reason = 'no goal'
        self.replans = 0
        self.forgets = 0
        self._path_xy = None
        self._next_retry = -math.inf
        self._replan_requested = False
        self._no_path_since = None
        self._spell_forgets = 0
        self._last_scan = None
        self._unswept_pose = None                # robot pose of a scan the turn sweep lacks
        self._last_stamp = None
        self.drive_guard = None
        if config.turn_sweep_memory > 0.0 and config.drive_guard_distance > 0.0:
            self.drive_guard = DriveGuard(
                config.drive_guard_distance, config.robot_length, config.robot_width,
                config.turn_sweep_margin, max_angular_speed=config.follower.max_angular_speed)
        self.turn_sweep = None if config.turn_sweep_memory == 0.0 else TurnSweep(
            config.turn_sweep_memory, config.robot_length, config.robot_width,
            config.turn_sweep_margin, spot_distance=config.turn_sweep_spot_distance,
            min_reach=0.0 if self.drive_guard is None else self.drive_guard.reach)
        self._init_not_getting_stuck(config)
        self.map_growths = 0
        self.map_growth_refusals = 0
        self.map_growth_refusal = ''
        self._refused_growth = None             # (geometry, growth) refused last
        self.real_laser = real_laser_switch_for(config, self.grid)
        self.real_laser_settings = {}
        self.real_laser_since = None
        self._real_laser_due = False            # the next observe switches
        self._laser_unwatched = False           # the last scan is not watched yet

    def _init_not_getting_stuck(self, config):
        """Set up the parts of issue 31 that ``config`` turns on (each None when off)."""
        shape = self.grid.geometry.shape
        windowed = hasattr(self.grid, 'last_window')       # the LabelGrid's update window
        self.stale_drops = 0
        self._confirmations = (ObstacleConfirmations(shape)
                               if config.stale_obstacle_age > 0.0 and windowed else None)
        continued = (config.wall_continuation_cost if config.wall_continuation_angle > 0.0
                     else 0.0)
        self._exploration = (ExplorationMemory(shape, config.unknown_cell_cost,
                                               config.forgotten_obstacle_cost, continued)
                             if windowed and (config.unknown_cell_cost > 0.0
                                              or config.forgotten_obstacle_cost > 0.0
                                              or continued > 0.0)
                             else None)
        self.commitment = None if config.route_block_distance == 0.0 else RouteCommitment(
            config.route_block_distance, config.route_switch_margin, config.mobile_wait_time,
            config.follower.max_linear_speed, config.resolution,
            blob_depth=2.0 * config.safety_radius + config.resolution,
            block_memory=config.route_block_memory)
        self._trusted_after = None             # the no-path spell ends at this stamp [s]
        self._next_wait_replan = -math.inf
        self._next_review = -math.inf          # the next route review (route_review_period) [s]
        self.route_reviews = 0
        self.give_way = None if config.give_way_time == 0.0 or not windowed else GiveWay(
            shape, config.give_way_time, config.give_way_distance, config.give_way_hold)
        self._give_way_follower = replace(config.follower, goal_approach_margin=0.0)

    def set_goal(self, x, y):
        """
        Set a new goal [m] in the map frame; the next step plans a path to it.

        Raises
        ------
        ValueError
            When the goal is not finite or lies outside the map.

        """
        x, y, _ = check_pose((x, y, 0.0), 'goal')      # finite, within MAX_POSE_COORDINATE
        rr, cc = self.grid.geometry.world_to_cell(x, y)
        if not self.grid.geometry.contains_cell(rr, cc):
            margin = self.config.map_growth_margin
            if self.config.map_growth_step == 0.0:
                raise ValueError(f'goal ({x:.2f}, {y:.2f}) m is outside the map')
            if not self.cover(x - margin, x + margin, y - margin, y + margin):
                raise ValueError(f'goal ({x:.2f}, {y:.2f}) m is outside the map, which may not '
                                 f'grow to it: {self.map_growth_refusal}')
        self.goal = (x, y)
        self.path = None
        self._path_xy = None
        self.status = NavigatorStatus.ACTIVE
        self.reason = ''
        self.replans = 0
        self.forgets = 0
        self._next_retry = -math.inf
        self._no_path_since = None
        self._spell_forgets = 0
        self.stale_drops = 0
        self.route_reviews = 0
        self._next_review = -math.inf
        self._trusted_after = None
        if self.commitment is not None:
            self.commitment.reset()
        if self.give_way is not None:
            self.give_way.reset()

    def clear_goal(self):
        """Drop the goal; the robot stops."""
        self.goal = None
        self.path = None
        self._path_xy = None
        self.status = NavigatorStatus.IDLE
        self.reason = 'no goal'

    def step(self, stamp, pose, ranges, angle_min, angle_increment, range_min, range_max,
             angle_max=None):
        """
        Fold one scan into the map and decide the next velocity command.

        The same as ``observe`` followed by ``decide``.

        Parameters
        ----------
        stamp : float
            Time of the scan [s], any monotonic clock (simulated time in the simulator).
        pose : (float, float, float)
            Robot base ``(x, y, yaw)`` in the map frame when the scan was taken [m, m, rad].
        ranges, angle_min, angle_increment, range_min, range_max, angle_max
            The laser scan, as for ``LabelGrid.update``.

        Returns
        -------
        NavigatorOutput

        Raises
        ------
        ValueError
            For a malformed scan or pose; the navigator's state is then unchanged.

        """
        self.observe(pose, ranges, angle_min, angle_increment, range_min, range_max, angle_max,
                     stamp=stamp)
        return self.decide(stamp, pose)

    def observe(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
                angle_max=None, stamp=None, defer_evidence=False, laser_pose=None):
        """
        Fold one scan into the map; the next ``decide`` replans if the scan asks for it.

        Split from ``decide`` so that a caller can publish the map before planning. The turn
        sweep takes the scan's hits at the next ``decide`` (or ``observe``), for the same
        reason; it only reads them there.

        Parameters
        ----------
        pose, ranges, angle_min, angle_increment, range_min, range_max, angle_max
            As for ``step``.
        stamp : float, optional
            Time of the scan [s]; needed when ``mobile_expiry`` is on.
        defer_evidence : bool
            Leave the free evidence of the scan for `settle` (``LabelGrid.update``), so that
            the map is ready sooner; the map and the plans are the same. Ignored by a grid
            without ``settle``.
        laser_pose : (float, float, float), optional
            The laser's ``(x, y, yaw)`` in the map frame [m, m, rad] when it is known apart
            from the base pose (from TF); None: ``pose`` composed with ``laser_offset``.

        Raises
        ------
        ValueError
            For a malformed scan or pose; the navigator's state is then unchanged.

        """
        pose = check_pose(pose)
        laser_pose = (compose(pose, self.config.laser_offset) if laser_pose is None
                      else check_pose(laser_pose, 'laser pose'))
        if self.config.map_growth_step > 0.0:
            self._grow_for_scan(pose, laser_pose, ranges, angle_min, angle_increment,
                                range_min, range_max)
        deferring = ({'defer_evidence': True} if defer_evidence and self.grid.defers_evidence
                     else {})
        switching = self._real_laser_due
        if switching:
            self._take_real_laser_settings(stamp)
        replan = self.grid.update(laser_pose, ranges, angle_min, angle_increment, range_min,
                                  range_max, self.config.safety_radius, path=self.path,
                                  angle_max=angle_max, stamp=stamp, **deferring)
        replan |= switching
        self._sweep_last_scan()
        self._replan_requested |= replan
        self._remember_scan(stamp)
        self._continue_walls(laser_pose, ranges, angle_min, angle_increment, range_min,
                             range_max)
        self._last_scan = (laser_pose, np.array(ranges, dtype=np.float64), angle_min,
                           angle_increment, range_min, range_max, angle_max, stamp)
        self._unswept_pose = pose if self.turn_sweep is not None else None
        self._laser_unwatched = True
        if not deferring:
            self._watch_laser()

    def _watch_laser(self):
        """
        Watch the last scan for a real laser on the move (``real_laser_switch``), once.

        Done after the labels are out (in `settle` with ``defer_evidence``): a scan that shows
        a real laser makes the next `observe` switch, before its update.
        """
        if (self.real_laser is None or self.real_laser.switched_at is not None
                or not self._laser_unwatched):
            return
        self._laser_unwatched = False
        laser_pose, ranges, _, _, range_min, range_max, _, stamp = self._last_scan
        self._real_laser_due = self.real_laser.watch(laser_pose[:2], ranges, range_min,
                                                     range_max, stamp)

    def _take_real_laser_settings(self, stamp):
        """
        Take the real-laser settings and start the map again, from the scan at ``stamp``.

        ``core.real_laser.take_real_laser_settings`` switches the grid's rule and resets it;
        the memories of the map start again too (the exploration memory, with the walls that
        go on, the obstacle confirmations, the route commitment, giving way); the counters
        stay.
        """
        self._real_laser_due = False
        self.config, self.real_laser_settings = take_real_laser_settings(self.config,
                                                                         self.grid)
        self.real_laser_since = stamp
        stale_drops, route_reviews = self.stale_drops, self.route_reviews
        self._init_not_getting_stuck(self.config)
        self.stale_drops, self.route_reviews = stale_drops, route_reviews

    def _grow_for_scan(self, pose, laser_pose, ranges, angle_min, angle_increment, range_min,
                       range_max):
        """
        Grow the map when the robot nears an edge or the scan hits beyond one.

        The robot keeps ``map_growth_margin`` from every edge; when a hit falls off the map,
        every hit keeps that margin too. Fields the update will refuse grow nothing.
        """
        margin = self.config.map_growth_margin
        x_min, x_max = pose[0] - margin, pose[0] + margin
        y_min, y_max = pose[1] - margin, pose[1] + margin
        geometry = self.grid.geometry
        x0, y0 = geometry.origin
        x1 = x0 + geometry.cols * geometry.resolution
        y1 = y0 + geometry.rows * geometry.resolution
        try:
            reach = scan_reach(ranges, range_min, range_max)
            # The hits lie within ``reach`` of the laser: their box only when that may cross.
            hits = (None if (laser_pose[0] - reach >= x0 and laser_pose[0] + reach < x1
                             and laser_pose[1] - reach >= y0 and laser_pose[1] + reach < y1)
                    else scan_hit_box(laser_pose, ranges, angle_min, angle_increment,
                                      range_min, range_max))
        except (TypeError, ValueError):
            hits = None
        if hits is not None and (hits[0] < x0 or hits[1] >= x1 or hits[2] < y0
                                 or hits[3] >= y1):
            x_min, x_max = min(x_min, hits[0] - margin), max(x_max, hits[1] + margin)
            y_min, y_max = min(y_min, hits[2] - margin), max(y_max, hits[3] + margin)
        if x_min < x0 or x_max > x1 or y_min < y0 or y_max > y1:
            self.cover(x_min, x_max, y_min, y_max)

    def cover(self, x_min, x_max, y_min, y_max):
        """
        Grow the map by whole blocks of ``map_growth_step`` until it covers a map-frame box.

        Parameters
        ----------
        x_min, x_max, y_min, y_max : float
            The box [m], finite.

        Returns
        -------
        bool
            Whether the map covers the box now; False also when growth is off
            (``map_growth_step`` 0) and it does not, or when the growth was refused
            (counted in ``map_growth_refusals`` once for each growth refused on the same map,
            the reason in ``map_growth_refusal``).

        """
        geometry = self.grid.geometry
        step = max(1, math.ceil(self.config.map_growth_step / geometry.resolution - 1e-9))
        growth = growth_to_cover(geometry, x_min, x_max, y_min, y_max, step)
        if not growth:
            return True
        if self.config.map_growth_step == 0.0:
            return False
        if self._refused_growth == (geometry, growth):
            return False                        # refused already: counted once
        reason = self._growth_refused(growth)
        if reason:
            self._refused_growth = (geometry, growth)
            self.map_growth_refusals += 1
            self.map_growth_refusal = reason
            return False
        self._grow(growth)
        return True

    def map_nbytes(self):
        """Return the bytes the per-cell arrays of the map and the planner hold."""
        parts = (self.grid, self._masks, self._confirmations, self._exploration, self.give_way)
        return sum(getattr(part, 'nbytes', 0) for part in parts if part is not None)

    def _growth_refused(self, growth):
        """Return why ``growth`` may not happen, or '' when it may."""
        if not hasattr(self.grid, 'grow'):
            return f'a {type(self.grid).__name__} cannot grow'
        old = self.grid.geometry
        new = growth.geometry(old)
        need = self.map_nbytes() * (new.rows * new.cols) / (old.rows * old.cols)
        limit = self.config.map_memory_limit
        if need > limit * 1e6:
            return (f'growing the map to {new.cols} x {new.rows} cells ({new.width:g} m x '
                    f'{new.height:g} m) would take {need / 1e6:.0f} MB, more than '
                    f'map_memory_limit {limit:g} MB')
        if new.rows * new.cols > MAX_MAP_CELLS:
            return (f'growing the map to {new.cols} x {new.rows} cells ({new.width:g} m x '
                    f'{new.height:g} m) would pass {MAX_MAP_CELLS:,} cells')
        surfaces = getattr(self.grid, 'surface_memory', None)
        if surfaces is not None and max(surfaces.cells_for(new)) > MAX_SURFACE_CELLS:
            return (f'the surface memory would have more than {MAX_SURFACE_CELLS} places a side '
                    f'over {new.width:g} m x {new.height:g} m (raise noise_margin)')
        return ''

    def _grow(self, growth):
        """Grow the grid and every per-cell array kept here; cells keep their places."""
        self.grid.grow(growth)
        geometry = self.grid.geometry
        self.config = replace(self.config, width=geometry.width, height=geometry.height,
                              origin=geometry.origin)
        self._masks.grow(growth)
        if self._confirmations is not None:
            self._confirmations.grow(growth, geometry.shape)
        if self._exploration is not None:
            self._exploration.grow(growth, geometry.shape)
        if self.give_way is not None:
            self.give_way.grow(growth, geometry.shape)
        if self.path is not None:
            self.path = self.path + np.array([growth.below, growth.left], dtype=np.int64)
        self.map_growths += 1

    def _continue_walls(self, laser_pose, ranges, angle_min, angle_increment, range_min,
                        range_max):
        """Mark the non-explored cells on the continuations of walls the scan grazes."""
        if self._exploration is None or self._exploration.continued is None:
            return
        ranges = read_no_echo(np.asarray(ranges, dtype=np.float64), range_min,
                              self.config.no_echo_below_range_min)
        points = continued_walls(ranges, angle_min, angle_increment, range_min, range_max,
                                 self.config.wall_continuation_angle,
                                 self.config.wall_continuation_reach)
        if points.shape[0] == 0:
            return
        cos_yaw, sin_yaw = math.cos(laser_pose[2]), math.sin(laser_pose[2])
        x = laser_pose[0] + cos_yaw * points[:, 0] - sin_yaw * points[:, 1]
        y = laser_pose[1] + sin_yaw * points[:, 0] + cos_yaw * points[:, 1]
        geometry = self.grid.geometry
        rows, cols = geometry.world_to_cell(x, y)
        inside = geometry.contains_cell(rows, cols)
        self._exploration.continue_walls(self.grid.labels, rows[inside], cols[inside])

    def _remember_scan(self, stamp):
        """Record the latest update's hits, obstacles and mobile cells (issue 31's parts)."""
        if self._confirmations is not None and stamp is not None:
            self._confirmations.observe(self.grid.last_window, stamp)
        if self._exploration is not None:
            self._exploration.observe(self.grid.labels, self.grid.last_window)
        if self.give_way is not None and stamp is not None:
            self.give_way.observe(self.grid.labels, self.grid.last_window, stamp)

    def settle(self):
        """Finish what the last ``observe`` with ``defer_evidence`` left for later."""
        self.grid.settle()
        self._watch_laser()

    def _sweep_last_scan(self):
        """Give the turn sweep the hits of the last scan observed, once."""
        if self._unswept_pose is None:
            return
        laser_pose, ranges, angle_min, angle_increment, range_min, range_max, _, stamp = \
            self._last_scan
        points = scan_points(laser_pose, ranges, angle_min, angle_increment, range_min,
                             range_max)
        self.turn_sweep.add_scan(
            stamp, self._unswept_pose[:2], np.column_stack((points.hits_x, points.hits_y)),
            view=(laser_pose, ranges, angle_min, angle_increment, range_min, range_max))
        self._unswept_pose = None

    def decide(self, stamp, pose):
        """
        Plan if needed and compute the velocity command for the robot at ``pose``.

        Parameters
        ----------
        stamp : float
            Current time [s].
        pose : (float, float, float)
            Robot base ``(x, y, yaw)`` in the map frame [m, m, rad].

        Returns
        -------
        NavigatorOutput

        """
        pose = check_pose(pose)
        self._sweep_last_scan()
        self._follow_clock(stamp)
        replan, self._replan_requested = self._replan_requested, False
        return self._decide(stamp, pose, replan)

    def _follow_clock(self, stamp):
        """
        Restart the no-path retry and forget timers when time goes backwards.

        Simulated time jumps back when the simulator restarts; a retry time or a no-path start
        kept from the old clock would hold the navigator without a plan until the new clock
        caught up with it.
        """
        if self._last_stamp is not None and stamp < self._last_stamp:
            self._next_retry = -math.inf
            self._next_wait_replan = -math.inf
            if self._no_path_since is not None:
                self._no_path_since = stamp
            if self._trusted_after is not None:
                self._trusted_after = stamp
        self._last_stamp = stamp

    def _decide(self, stamp, pose, replan_flag):
        if self.goal is None:
            return NavigatorOutput(STOP, self.status, self.reason)
        if self.status is NavigatorStatus.GOAL_REACHED:
            return NavigatorOutput(STOP, self.status, self.reason)
        if self.give_way is not None:
            giving_way = self._give_way(stamp, pose)
            if giving_way is not None:
                return giving_way
        replanned = False
        cause = ReplanCause.NONE
        waiting_replan = (self.commitment is not None and self.commitment.waited > 0.0
                          and stamp >= self._next_wait_replan)
        stale = replan_flag or waiting_replan or self._path_is_stale(pose)
        if not stale and self._review_route(stamp, pose):
            replanned, cause = True, ReplanCause.OTHER
        if stale:
            if self.path is None and stamp < self._next_retry:
                return NavigatorOutput(STOP, self.status, self.reason)
            if self.path is None and self.status is NavigatorStatus.NO_PATH:
                cause = ReplanCause.NO_PATH_RETRY
            else:
                cause = ReplanCause.FLAG if replan_flag else ReplanCause.OTHER
            if self.path is None and self._forget_is_due(stamp):
                self._forget_unseen_obstacles(pose)
                self._no_path_since = stamp
            terms = self._planning_terms(pose)
            replanned = self._plan(pose, terms)
            if self.path is None and self._drop_stale_obstacles(pose, stamp, terms):
                # The same replan, searched again without the stale cells: counted once.
                replanned = self._plan(pose, self._planning_terms(pose), count=False)
            if self.path is None:
                self._next_retry = stamp + self.config.no_path_retry_period
                if self._no_path_since is None:
                    self._no_path_since = stamp
                self._trusted_after = None
                return NavigatorOutput(STOP, self.status, self.reason, replanned, cause)
            self._trust_new_path(stamp)
        self._end_spell_if_trusted(stamp)
        if self._must_wait(pose, stamp):
            self.reason = 'waiting for a mobile obstacle ahead'
            return NavigatorOutput(STOP, self.status, self.reason, replanned, cause)
        self.reason = ''
        command = follow_path(pose, self._path_xy, self.config.follower)
        if command.goal_reached:
            self.status = NavigatorStatus.GOAL_REACHED
            self.reason = 'inside the goal tolerance'
            return NavigatorOutput(STOP, self.status, self.reason, replanned, cause)
        return NavigatorOutput(self._guarded(command, pose), self.status, self.reason,
                               replanned, cause)

    def _guarded(self, command, pose):
        """Return ``command`` as the turn sweep and the drive guard let it through."""
        if self.turn_sweep is not None:
            swept = self.turn_sweep.check(command, pose, self._obstacle_at)
            # The sweep's own drive to a turn place is checked on its straight way there.
            if self.drive_guard is not None and swept is command and command.linear > 0.0:
                swept = self.drive_guard.check(command, self.turn_sweep.points(
                    pose, self._obstacle_at, within=self.drive_guard.reach))
            command = swept
        return command

    def _review_route(self, stamp, pose):
        """
        Every ``route_review_period``, plan again and take a plan cheaper by the review margin.

        The paper plans again only when a cell of the path turns obstacle. A detour taken
        because a wanderer blocked the corridor ahead is then driven to its end, however long,
        after the corridor has opened again: nothing on the detour changes. The review finds
        the shorter route; ``route_review_margin`` (at least ``route_switch_margin``) keeps it
        from trading one route for another of about the same cost.

        Returns
        -------
        switched : bool
            True when the review replaced the route (counted in ``replans`` and
            ``route_reviews``).

        """
        period = self.config.route_review_period
        if (period == 0.0 or self.commitment is None or self.path is None
                or stamp < self._next_review):
            return False
        self._next_review = stamp + period
        route = (self.path, self._path_xy, self.status, self.reason)
        self._plan(pose, self._planning_terms(pose), count=False, review=True)
        if self.path is None:
            # A review never drops the route (the planning masks may block a cell of it that
            # the labels do not): whether it is blocked is the usual replan's to say.
            self.path, self._path_xy, self.status, self.reason = route
            return False
        if self.path is route[0]:
            return False
        self.replans += 1
        self.route_reviews += 1
        self._trust_new_path(stamp)
        return True

    def _give_way(self, stamp, pose):
        """
        Drive to, or wait at, the place the robot gives way from (``GiveWay``).

        Returns the step's output while giving way, None otherwise (plan and follow as usual).
        The way is given up when a cell of it ahead turns obstacle or the drive takes too long
        (``GiveWay.given_up``); the wait at the place ends when a way to the goal has opened
        (`_way_open`) or after ``give_way_hold``; then the robot plans to its goal again.
        """
        give_way = self.give_way
        radius = self.config.safety_radius
        if not give_way.active:
            give_way.note(stamp, pose[:2])
            if not (give_way.due(stamp) and give_way.start(self.grid, pose[:2], radius, stamp)):
                return None
        if give_way.arrived(stamp, pose[:2]):
            if give_way.done(stamp):
                return self._end_give_way()
            turn = give_way.facing_error(pose)
            if abs(turn) > FACE_TOLERANCE:
                follower = self.config.follower
                angular = max(-follower.max_angular_speed,
                              min(follower.max_angular_speed, follower.heading_gain * turn))
                self.reason = 'giving way: turning to face the agent'
                return NavigatorOutput(self._guarded(VelocityCommand(0.0, angular, turn=turn),
                                                     pose), self.status, self.reason)
            if self._way_open(stamp, pose):
                return self._end_give_way()
            self.reason = 'giving way: waiting for an agent to pass'
            return NavigatorOutput(STOP, self.status, self.reason)
        if give_way.given_up(stamp, self.grid, pose[:2], self.config.follower.max_linear_speed):
            return self._end_give_way()
        command = follow_path(pose, give_way.way_xy, self._give_way_follower)
        if command.goal_reached:
            give_way.arrived(stamp, give_way.way_xy[-1])
            command = STOP
        self.reason = 'giving way: driving aside for an agent'
        return NavigatorOutput(self._guarded(command, pose), self.status, self.reason)

    def _way_open(self, stamp, pose):
        """
        Tell whether, while the robot waits at its place, a way to the goal has opened.

        Planned every ``no_path_retry_period``: a path that enters no agent's cell (route
        commitment plans through far mobile cells at the cost of a wait) and on which the
        robot need not wait (the agent moved off, or a way round it was found).
        """
        if stamp < self._next_retry:
            return False
        self._next_retry = stamp + self.config.no_path_retry_period
        self._plan(pose, self._planning_terms(pose))
        return (self.path is not None
                and not self.give_way.crosses_agents(self.path, self.grid.labels, stamp)
                and not self._must_wait(pose, stamp))

    def _end_give_way(self):
        """End giving way: the next step plans to the goal from where the robot is."""
        self.give_way.reset()
        self.path = None
        self._path_xy = None
        self._next_retry = -math.inf
        return None

    def _closest_on_path(self, pose):
        """Return the index of the path point closest to the robot, and its distance [m]."""
        distance = np.hypot(self._path_xy[:, 0] - pose[0], self._path_xy[:, 1] - pose[1])
        closest = int(np.argmin(distance))
        return closest, float(distance[closest])

    def _path_is_stale(self, pose):
        """
        Tell whether there is no path, a cell ahead on it is blocked, or the robot left it.

        With route commitment, the mobile cells A* plans through do not block
        (``RouteCommitment.opens``).
        """
        if self.path is None:
            return True
        closest, distance = self._closest_on_path(pose)
        if distance > self.config.max_path_deviation:
            return True
        ahead = self.path[closest + 1:]
        labels = self.grid.labels[ahead[:, 0], ahead[:, 1]]
        blocked = blocked_mask(labels)
        if self.commitment is not None:
            blocked &= ~self.commitment.opens(labels, self._path_xy[closest + 1:], pose[:2])
        return bool(blocked.any())

    def _planning_terms(self, pose):
        """
        Return what A* adds to the planning masks: ``(extra_cost, opened)``, each maybe None.

        ``extra_cost`` [cells] holds the exploration costs and the wait in front of near mobile
        cells; ``opened`` the mobile cells planned through (route commitment).
        """
        labels = self.grid.labels
        extra = opened = None
        if self._exploration is not None:
            extra = self._exploration.cost(labels)
        if self.commitment is not None:
            opened, wait = self.commitment.mobile_terms(labels, self.grid.geometry, pose[:2])
            extra = wait if extra is None else extra + wait
        return extra, opened

    def _plan(self, pose, terms=(None, None), count=True, review=False):
        """
        Plan from the robot's cell to the goal's; set path, status and reason.

        ``count``: add one to ``replans`` (not for a second search within one replan);
        ``review``: a route review (`_review_route`), whose plan must beat the route by
        ``route_review_margin``.
        """
        geometry = self.grid.geometry
        start = tuple(int(v) for v in geometry.world_to_cell(pose[0], pose[1]))
        goal = tuple(int(v) for v in geometry.world_to_cell(*self.goal))
        self.replans += int(count)
        if not geometry.contains_cell(*start):
            return self._no_path('the robot is outside the map')
        self._masks.refresh()
        extra, opened = terms
        if self._masks.blocked[goal] and (opened is None or not opened[goal]):
            return self._no_path('the goal cell is an obstacle')
        # No diagonal past a blocked cell: r equals the Husky's circumscribed radius, so the
        # half-cell a cut corner saves would bring the robot's corners to the wall.
        cells = self._masks.plan(start, goal, self._footprint(pose), cut_corners=False,
                                 extra_cost=extra, opened=opened)
        if self._keeps_current_route(pose, cells, extra, opened, review):
            return True
        if cells is None:
            return self._no_path('no path to the goal on the current map')
        self.path = np.array(cells, dtype=np.int64)
        path_x, path_y = geometry.cell_to_world(self.path[:, 0], self.path[:, 1])
        self._path_xy = np.column_stack((path_x, path_y))
        self._path_xy[-1] = self.goal                  # aim at the goal itself, not its cell
        self.status = NavigatorStatus.ACTIVE
        self.reason = ''
        return True

    def _keeps_current_route(self, pose, cells, extra, opened, review=False):
        """
        Tell whether the current route stays instead of the new plan ``cells`` (or None).

        Only with route commitment, a path being followed (the robot within
        ``max_path_deviation`` of it), and the rest of it not blocked: it stays unless the new
        plan is cheaper by ``route_switch_margin`` (by ``route_review_margin``, and at least
        that, for a route review, which the commitment does not count), and it stays whatever
        the cost when the new plan enters a cell that blocked a route within
        ``route_block_memory``. A route left because it is blocked leaves its blocked cells
        to that memory.
        """
        if self.commitment is None or self.path is None:
            return False
        closest, distance = self._closest_on_path(pose)
        if distance > self.config.max_path_deviation:
            return False
        blocked = self._masks.blocked if opened is None else self._masks.blocked & ~opened
        cost = self._masks.cost
        if extra is not None:
            cost = extra if cost is None else cost + extra
        current = self.commitment.route_cost(self.path[closest:], blocked, cost)
        new = (math.inf if cells is None
               else self.commitment.route_cost(np.array(cells, dtype=np.int64), blocked, cost))
        stamp = self._last_stamp
        if not math.isfinite(current):
            if stamp is not None:
                ahead = self.path[closest + 1:]
                self.commitment.note_blockers(
                    self._cell_centres(ahead[blocked[ahead[:, 0], ahead[:, 1]]]), stamp)
            return False
        if (cells is not None and stamp is not None
                and self.commitment.enters_blocker(self._cell_centres(cells), stamp)):
            self.commitment.held_back += 1
            return True
        if not review:
            return self.commitment.keep_current(current, new)
        margin = max(self.config.route_review_margin, self.config.route_switch_margin)
        return self.commitment.keep_current(current, new, margin, count=False)

    def _cell_centres(self, cells):
        """Return the centres [m] of ``(row, col)`` cells, (N, 2) float64, map frame."""
        cells = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
        x, y = self.grid.geometry.cell_to_world(cells[:, 0], cells[:, 1])
        return np.column_stack((x, y)).astype(np.float64)

    def _drop_stale_obstacles(self, pose, stamp, terms):
        """
        With no path, drop the stale obstacle cells that alone close the route.

        Plans again with the obstacle cells no hit confirmed for ``stale_obstacle_age`` opened
        (at `STALE_CELL_COST` and their hits each, so that the search crosses as few and as
        rarely seen ones as it can) and drops
        those on the path found (``ObstacleConfirmations.drop``); cells within
        ``FORGET_KEEP_RADII`` safety radii of the robot are kept.

        Returns
        -------
        dropped : bool
            True when cells were dropped (plan again).

        """
        if self._confirmations is None or self.goal is None:
            return False
        geometry = self.grid.geometry
        start = tuple(int(v) for v in geometry.world_to_cell(pose[0], pose[1]))
        goal = tuple(int(v) for v in geometry.world_to_cell(*self.goal))
        if not geometry.contains_cell(*start):
            return False
        self.settle()
        stale = self._confirmations.stale(self.grid.labels, stamp, self.config.stale_obstacle_age)
        rows, cols, near = self._footprint(pose, FORGET_KEEP_RADII * self.config.safety_radius)
        stale[rows, cols] &= ~near
        if not stale.any():
            return False
        extra, opened = terms
        opened = stale if opened is None else opened | stale
        stale_cost = np.where(stale, STALE_CELL_COST + self._confirmations.hits, 0.0)
        extra = stale_cost if extra is None else extra + stale_cost
        cells = self._masks.plan(start, goal, self._footprint(pose), cut_corners=False,
                                 extra_cost=extra, opened=opened)
        if cells is None:
            return False
        cells = np.array(cells, dtype=np.int64)
        on_path = cells[stale[cells[:, 0], cells[:, 1]]]
        if not self._confirmations.drop(self.grid, on_path):
            return False
        self.stale_drops += 1
        return True

    def _trust_new_path(self, stamp):
        """Start the trust period of a path found in a no-path spell (``path_trust_time``)."""
        if self._no_path_since is None:
            return
        if self.config.path_trust_time == 0.0:
            self._no_path_since = None
            self._spell_forgets = 0
        elif self._trusted_after is None:
            self._trusted_after = stamp + self.config.path_trust_time

    def _end_spell_if_trusted(self, stamp):
        """End the no-path spell once a path has lasted ``path_trust_time``."""
        if self._trusted_after is not None and stamp >= self._trusted_after:
            self._no_path_since = None
            self._spell_forgets = 0
            self._trusted_after = None

    def _must_wait(self, pose, stamp):
        """Tell whether the robot waits in front of a mobile obstacle on its path."""
        if self.commitment is None or self.commitment.wait_time == 0.0 or self.path is None:
            return False
        closest, _ = self._closest_on_path(pose)
        wait = self.commitment.must_wait(self.path, self._path_xy, closest, self.grid.labels,
                                         stamp)
        if wait and stamp >= self._next_wait_replan:
            self._next_wait_replan = stamp + self.config.no_path_retry_period
        return wait

    def _forget_is_due(self, stamp):
        """Tell whether there has been no path for ``forget_obstacles_after`` seconds."""
        after = self.config.forget_obstacles_after
        return (after > 0.0 and self._no_path_since is not None
                and stamp - self._no_path_since >= after and self._last_scan is not None)

    def _forget_unseen_obstacles(self, pose):
        """
        Forget obstacle cells, then fold the latest scan in again.

        The first time in a spell without a path, mobile obstacles go back to explored; after
        that, every obstacle cell goes back to non-explored. Cells within
        ``FORGET_KEEP_RADII`` safety radii of the robot are kept: the robot may have to turn in
        place beside them before the laser sees them again.
        """
        self.settle()                   # the deferred evidence reads the labels as they were
        self.grid.forget_obstacles(pose[:2], FORGET_KEEP_RADII * self.config.safety_radius,
                                   every_obstacle=self._spell_forgets > 0)
        laser_pose, ranges, angle_min, angle_increment, range_min, range_max, angle_max, \
            stamp = self._last_scan
        self.grid.update(laser_pose, ranges, angle_min, angle_increment, range_min, range_max,
                         self.config.safety_radius, angle_max=angle_max, stamp=stamp)
        self.forgets += 1
        self._spell_forgets += 1

    def _no_path(self, reason):
        self.path = None
        self._path_xy = None
        self.status = NavigatorStatus.NO_PATH
        self.reason = reason
        return True

    def _obstacle_at(self, xy):
        """Tell which map-frame points (N, 2) [m] lie on cells the grid holds as obstacles."""
        geometry = self.grid.geometry
        rr, cc = geometry.world_to_cell(xy[:, 0], xy[:, 1])
        inside = geometry.contains_cell(rr, cc)
        obstacle = np.zeros(xy.shape[0], dtype=bool)
        obstacle[inside] = blocked_mask(self.grid.labels[rr[inside], cc[inside]])
        return obstacle

    def _footprint(self, pose, radius=None):
        """
        Return the window around the robot and its cells within ``radius`` [m].

        ``footprint_radius`` by default.
        """
        geometry = self.grid.geometry
        radius = self.config.footprint_radius if radius is None else radius
        rows, cols = geometry.cell_window(pose[0] - radius, pose[0] + radius,
                                          pose[1] - radius, pose[1] + radius)
        x_centres, y_centres = geometry.window_centres(rows, cols)
        near = np.hypot(x_centres[None, :] - pose[0], y_centres[:, None] - pose[1]) <= radius
        return rows, cols, near

    @property
    def path_xy(self):
        """Return the planned path in the map frame, (N, 2) float64 [m], or None."""
        return self._path_xy


def warm_up_navigator():
    """
    Compile (or load from the cache) the kernels a `Navigator` on a ``LabelGrid`` runs.

    The label update (every rule part), the walls that go on, the planning masks and A*; a
    process calls it once at start, so that its first scan does not wait for them.

    Returns
    -------
    seconds : float
        Wall time it took [s]: the compile time with an empty cache, the load time with a
        warm one, nearly 0 when the kernels were ready already.

    """
    started = time.perf_counter()
    warm_up_label_update()
    warm_up_wall_continuation()
    warm_up_planning_masks()
    warm_up_astar()
    return time.perf_counter() - started
