"""
One benchmark episode without ROS: the navigator and the pybullet world in lockstep.

The same ``Navigator`` the ``dpn`` node wraps drives the same ``World`` the ``pybullet_world``
node wraps, scan by scan, as fast as the CPU allows and deterministically for a seed.

Episode rules (``docs/benchmark.md``; the constants in ``episode_metrics``):

- The time limit is ``30 s + 3 * L / v_ref``. ``L`` is the task's shortest path on the true
  map, for a robot that keeps 0.35 m (the Husky's half width) from walls, and ``v_ref`` is one
  fixed reference speed for every navigator (``episode_metrics.REFERENCE_SPEED``, 1 m/s), not
  the speed a navigator declares.
- The episode ends when the benchmark sees the true pose within
  ``episode_metrics.GOAL_TOLERANCE`` of the goal, when the navigator reports the goal reached,
  or at the time limit.
- **Success** is the benchmark's: the true pose within the tolerance before the time limit,
  with no contact. ``end_reason`` says why an episode failed as the benchmark sees it
  (``episode_metrics.end_reason``: collision, false arrival, no path, stuck, oscillating,
  timeout while moving). The older ``failure`` column keeps its coarse reasons:
  - ``collision`` when the Husky touched a wall or a wanderer, even if it then arrived;
  - ``no_path`` when the navigator ended with no path;
  - ``timeout`` otherwise.

"""

import dataclasses
from dataclasses import dataclass, field
import math
import time

import numpy as np

from .baselines.costmap_grid import CostmapConfig, CostmapGrid
from .baselines.nav2_navigator import Nav2Navigator
from .baselines.oracle_grid import OracleGrid
from .baselines.spacetime_oracle import SpaceTimeOracle
from .baselines.wanderer_forecast import forecast_positions
from .detection import DETECTION_FIELDS, DetectionMeter
from .episode_metrics import GOAL_TOLERANCE, METRIC_FIELDS, time_limit as rule_time_limit
from .episode_metrics import TrajectoryRecorder
from .ground_truth import wall_belt, wanderer_hit_points
from .navigator_plugin import PluginNavigator
from ..core import astar, CellLabel, Navigator, NavigatorConfig, NavigatorStatus, path_cost
from ..core.grid_geometry import GridGeometry
from ..core.pose2d import compose

#: The Husky's half width [m]: the clearance of the reference shortest path.
HUSKY_HALF_WIDTH = 0.35
#: Cell side of the grid the reference shortest path is planned on [m].
REFERENCE_CELL = 0.25
#: Stream of the pose-noise generator, beside the episode's seed (the world has its own).
POSE_NOISE_STREAM = 0x9E3779B9
#: Cell side of the costmap navigator's obstacle layer [m] (Nav2's costmaps: 0.05 to 0.1 m).
COSTMAP_LAYER_RESOLUTION = 0.1


@dataclass(frozen=True)
class EpisodeResult:
    """
    What one episode measured.

    Attributes
    ----------
    scenario, task, wanderers, seed
        What was run.
    success : bool
        Goal reached with no contact.
    failure : str
        ``''``, ``'collision'``, ``'no_path'`` or ``'timeout'``.
    time : float
        Simulated time at the end [s].
    time_limit : float
        [s]
    path_length : float
        Distance the Husky travelled [m].
    shortest_path : float
        The reference shortest path ``L`` [m].
    replans : int
        Paths planned by the navigator.
    forgets : int
        Times the navigator, stuck with no path, forgot the obstacles out of view
        (``NavigatorConfig.forget_obstacles_after``).
    wall_contacts, wanderer_contacts : int
        Contact events of the Husky (``ContactLog``).
    robot_caused_contacts, agent_caused_contacts : int
        The wanderer contact events split by who closed the gap (``sim_bridge.contacts``):
        the Husky moving towards the agent, or the agent walking into a Husky that stood or
        moved away.
    walls_labelled_mobile : int
        Cells labelled mobile obstacle at the end within a wall's f1 belt (the paper's
        classification errors; see ``map_quality``).
    ghost_obstacles : int
        Cells labelled mobile obstacle at the end that no wall or wanderer explains.
    detection : DetectionResult or None
        The map measured as a detector, scan by scan (``detection.DetectionMeter``); None
        when the episode ran without it.
    metrics : EpisodeMetrics or None
        The benchmark's own view of the episode (``episode_metrics``).
    detection_wall_time : float or None
        Wall-clock time spent measuring it [s]; left out of comparisons, as it varies.

    """

    scenario: str
    task: int
    wanderers: int
    seed: int
    success: bool
    failure: str
    time: float
    time_limit: float
    path_length: float
    shortest_path: float
    replans: int
    forgets: int
    wall_contacts: int
    wanderer_contacts: int
    robot_caused_contacts: int
    agent_caused_contacts: int
    walls_labelled_mobile: int
    ghost_obstacles: int
    detection: object = None
    metrics: object = None
    detection_wall_time: float = field(default=None, compare=False)

    def as_row(self):
        """Return the result as a flat dict, for CSV writing (detection fields None if off)."""
        row = {name: getattr(self, name) for name in self.__dataclass_fields__}
        detection = row.pop('detection')
        metrics = row.pop('metrics')
        row.update(metrics.as_row() if metrics is not None else dict.fromkeys(METRIC_FIELDS))
        row.update(detection.as_row() if detection is not None else
                   dict.fromkeys(DETECTION_FIELDS))
        return row


def shortest_path_length(scenario, task):
    """
    Return the task's shortest path [m] for a robot keeping ``HUSKY_HALF_WIDTH`` from walls.

    Planned with the core's A* on a ``REFERENCE_CELL`` grid; ``inf`` when there is none.
    """
    from sim_bridge.free_space import clearance_grid
    grid = clearance_grid(scenario.free, scenario.geometry, HUSKY_HALF_WIDTH,
                          cell_size=REFERENCE_CELL)
    start = tuple(int(v) for v in grid.geometry.world_to_cell(*task.start[:2]))
    goal = tuple(int(v) for v in grid.geometry.world_to_cell(*task.goal))
    if not (grid.geometry.contains_cell(*start) and grid.geometry.contains_cell(*goal)):
        return math.inf
    path = astar(~grid.clear, start, goal)
    return math.inf if path is None else path_cost(path) * grid.geometry.resolution


@dataclass(frozen=True, eq=False)
class TaskSetup:
    """
    What every episode of one scenario and task computes alike, whatever its wanderers.

    Attributes
    ----------
    shortest_path : float
        `shortest_path_length` of the task [m].
    wanderer_grid : sim_bridge.free_space.ClearanceGrid
        The wanderers' clearance grid of the scenario (default `WandererConfig`), read-only.
        It does not depend on the task.

    """

    shortest_path: float
    wanderer_grid: object


def task_setup(scenario, task_index, wanderer_grid=None):
    """
    Compute the `TaskSetup` of a scenario's task.

    Parameters
    ----------
    scenario : sim_bridge.scenario.Scenario
        The map and its tasks.
    task_index : int
        Which of its tasks.
    wanderer_grid : sim_bridge.free_space.ClearanceGrid, optional
        The scenario's wanderer grid from an earlier `TaskSetup` of another task (it does
        not depend on the task); built here by default.

    Returns
    -------
    TaskSetup

    """
    if wanderer_grid is None:
        from sim_bridge.world import wanderer_clearance_grid, WorldConfig
        wanderer_grid = wanderer_clearance_grid(scenario, WorldConfig().wanderer)
    return TaskSetup(shortest_path_length(scenario, scenario.tasks[task_index]), wanderer_grid)


def map_quality(labels, geometry, truth_occupied, truth_geometry, wanderer_xy, wanderer_radius,
                safety_radius):
    """
    Count the map's mobile-obstacle labels that ground truth does not explain.

    f1 marks cells within the safety radius ``r`` of a hit, so a wall or a robot makes a belt
    of obstacle cells ``r`` wide around itself; both counts allow for it.

    Parameters
    ----------
    labels : (H, W) ndarray of uint8
        The navigator's labels on ``geometry``.
    geometry : GridGeometry
        The navigator's grid.
    truth_occupied : (h, w) ndarray of bool
        The true walls on ``truth_geometry`` (usually finer).
    truth_geometry : GridGeometry
        The ground-truth grid.
    wanderer_xy : (K, 2) ndarray of float
        Wanderer positions at the end [m].
    wanderer_radius : float
        Their circumscribed radius [m].
    safety_radius : float
        The navigator's f1 radius ``r`` [m].

    Returns
    -------
    walls_labelled_mobile : int
        Cells labelled mobile obstacle within ``ceil(r / res)`` cells (Chebyshev) of a cell
        that holds a wall pixel: the paper's classification errors.
    ghost_obstacles : int
        The other cells labelled mobile obstacle whose centre is farther than
        ``wanderer_radius + r`` from every wanderer: obstacles left where no robot is.

    """
    rr, cc = np.nonzero(truth_occupied)
    x, y = truth_geometry.cell_to_world(rr, cc)
    wall_rr, wall_cc = geometry.world_to_cell(x, y)
    on_grid = geometry.contains_cell(wall_rr, wall_cc)
    has_wall = np.zeros(geometry.shape, dtype=bool)
    has_wall[wall_rr[on_grid], wall_cc[on_grid]] = True
    # Dilate by k cells: a wall's f1 belt.
    k = math.ceil(safety_radius / geometry.resolution)
    padded = np.pad(has_wall, k)
    near_wall = np.zeros_like(has_wall)
    for dr in range(2 * k + 1):
        for dc in range(2 * k + 1):
            near_wall |= padded[dr:dr + has_wall.shape[0], dc:dc + has_wall.shape[1]]
    mobile = labels == CellLabel.MOBILE_OBSTACLE
    mobile_rr, mobile_cc = np.nonzero(mobile & ~near_wall)
    centre_x, centre_y = geometry.cell_to_world(mobile_rr, mobile_cc)
    wanderer_xy = np.asarray(wanderer_xy, dtype=np.float64).reshape(-1, 2)
    if wanderer_xy.shape[0]:
        distance = np.hypot(centre_x[:, None] - wanderer_xy[None, :, 0],
                            centre_y[:, None] - wanderer_xy[None, :, 1]).min(axis=1)
        ghosts = int(np.count_nonzero(distance > wanderer_radius + safety_radius))
    else:
        ghosts = int(mobile_rr.shape[0])
    return int(np.count_nonzero(mobile & near_wall)), ghosts


def build_map(map_model, navigator_config, scenario, wanderer_radius, range_max):
    """
    Build the map a navigator variant plans on (``protocol.MAP_MODELS``).

    Parameters
    ----------
    map_model : str
        ``'labels'`` (the paper's ``LabelGrid``), ``'costmap'`` or ``'nav2'`` (``CostmapGrid``
        with Nav2 Jazzy's default ranges scaled to the laser, its layer in
        ``COSTMAP_LAYER_RESOLUTION`` cells; ``nav2`` runs it with ``Nav2Navigator``) or
        ``'oracle'``, ``'foresight'`` or ``'spacetime'`` (``OracleGrid``; ``foresight`` is fed
        the agents' forecast positions near the robot, ``baselines.wanderer_forecast``;
        ``spacetime`` holds the walls alone, and ``SpaceTimeOracle`` plans on it with the
        agents' true future).
    navigator_config : NavigatorConfig
        Its grid size, resolution, origin and safety radius are the map's.
    scenario : sim_bridge.scenario.Scenario
        The true walls, for the oracle.
    wanderer_radius : float
        The wanderers' circumscribed radius [m], for the oracle.
    range_max : float
        The laser's ``range_max`` [m], for the costmap's ranges.

    Returns
    -------
    grid : LabelGrid, CostmapGrid or OracleGrid, or None
        None for ``'labels'``: the ``Navigator`` builds its own.

    Raises
    ------
    ValueError
        For an unknown map model.

    """
    if map_model == 'labels':
        return None
    config = navigator_config
    if map_model in ('costmap', 'nav2'):
        return CostmapGrid(config.width, config.height, config.resolution, config.origin,
                           CostmapConfig.scaled_to_laser(range_max),
                           layer_resolution=COSTMAP_LAYER_RESOLUTION)
    if map_model in ('oracle', 'foresight', 'spacetime'):
        geometry = GridGeometry(config.width, config.height, config.resolution,
                                tuple(config.origin))
        belt = wall_belt(scenario.occupied, scenario.geometry, geometry, config.safety_radius)
        return OracleGrid(geometry, belt, wanderer_radius + config.safety_radius)
    raise ValueError(f'unknown map model {map_model!r}: labels, costmap, nav2, oracle, '
                     'foresight or spacetime')


def run_episode(scenario, task_index, wanderers, seed, navigator_config=None,
                time_limit=None, recorder=None, navigator_options=None, detection=True,
                setup=None, map_model='labels', wanderer_config=None, pose_noise=None,
                navigator_class=None, laser=None):
    """
    Run one episode in lockstep and measure it.

    Parameters
    ----------
    scenario : sim_bridge.scenario.Scenario
        The map and its tasks.
    task_index : int
        Which of the scenario's tasks.
    wanderers : int
        Number of wandering P3-ATs, 0 to 10.
    seed : int
        Seed of the world (wanderers).
    navigator_config : NavigatorConfig, optional
        Default: the scenario's size and origin, the laser mount, and default limits.
    time_limit : float, optional
        Overrides the rule's limit [s].
    navigator_options : dict, optional
        ``NavigatorConfig`` fields to override in the default configuration (e.g.
        ``protocol.NAVIGATORS['paper']``); not with ``navigator_config``.
    recorder : callable, optional
        Called as ``recorder(world, navigator)`` once per scan, after the navigator has
        processed it (e.g. an `EpisodeRecorder`); must not change either.
    detection : bool
        Measure the map as a detector after every scan (``EpisodeResult.detection``); it
        reads the navigator and the world and changes neither.
    setup : TaskSetup, optional
        This scenario's and task's setup (`task_setup`), when the caller keeps it between
        episodes (a benchmark worker does); computed here by default.
    map_model : str
        The map the navigator plans on (`build_map`); the oracle's map reads the wanderers'
        true positions before every step and has no detection measures.
    wanderer_config : sim_bridge.wanderers.WandererConfig, optional
        The wanderers' behaviour (default: ``WorldConfig``'s); its ``clearance`` must be the
        one ``setup``'s wanderer grid was built for (``AGENT_MODELS`` has the presets).
    pose_noise : (float, float), optional
        Standard deviations of the pose the navigator is given [m, rad]: Gaussian, drawn per
        scan from a generator seeded by ``seed`` (the benchmark judges the true pose).
    navigator_class : type, optional
        A plug-in navigator (``navigator_plugin``), built as ``navigator_class(config)`` in
        place of the built-in one; ``map_model`` is then unused, and there are no detection or
        map-quality measures.
    laser : sim_bridge.laser.LaserConfig, optional
        The world's laser (default: ``WorldConfig``'s, the ``ideal`` profile). The navigator
        reads the beam layout and range limits from each scan, and its default configuration
        takes the laser's mount.

    Returns
    -------
    EpisodeResult

    """
    from sim_bridge.world import World, WorldConfig
    task = scenario.tasks[task_index]
    world_config = WorldConfig(n_wanderers=wanderers, seed=seed)
    if laser is not None:
        world_config = dataclasses.replace(world_config, laser=laser)
    if navigator_config is None:
        navigator_config = NavigatorConfig(width=scenario.width, height=scenario.height,
                                           origin=scenario.origin,
                                           laser_offset=world_config.laser.mount,
                                           **(navigator_options or {}))
    elif navigator_options:
        raise ValueError('give navigator_config or navigator_options, not both')
    if setup is None:
        setup = task_setup(scenario, task_index)
    shortest = setup.shortest_path
    if time_limit is None:
        time_limit = rule_time_limit(shortest)
    travelled = 0.0
    if wanderer_config is not None:
        world_config = dataclasses.replace(world_config, wanderer=wanderer_config)
    with World(scenario, world_config, start=task.start,
               wanderer_grid=setup.wanderer_grid) as world:
        scan = world.scan()
        if navigator_class is not None:
            navigator = PluginNavigator(navigator_class(navigator_config))
            map_model = 'plugin'
            detection = False
        else:
            grid = build_map(map_model, navigator_config, scenario, world.wanderer_radius,
                             scan.range_max)
            if map_model == 'nav2':
                navigator = Nav2Navigator(navigator_config, grid)
            elif map_model == 'spacetime':
                navigator = SpaceTimeOracle(
                    navigator_config, grid, world.forecast_wanderers,
                    world.wanderer_radius + navigator_config.safety_radius)
            else:
                navigator = Navigator(navigator_config, grid)
        noise = None
        if pose_noise is not None and any(pose_noise):
            noise = (np.random.default_rng([seed, POSE_NOISE_STREAM]),
                     np.array([pose_noise[0], pose_noise[0], pose_noise[1]], dtype=float))
        navigator.set_goal(*task.goal)
        oracle = map_model in ('oracle', 'foresight', 'spacetime')
        forecast = None
        if map_model == 'foresight':
            forecast = {'reach': world.wanderer_radius + navigator_config.safety_radius,
                        'previous': None, 'time': world.time}
        last_xy = world.husky_pose[:2]
        trajectory = TrajectoryRecorder(world.wanderer_radius)
        meter = None
        if detection and not oracle:
            started = time.perf_counter()
            meter = DetectionMeter(
                navigator.grid.geometry,
                wall_belt(scenario.occupied, scenario.geometry, navigator.grid.geometry,
                          navigator_config.safety_radius),
                world.wanderer_radius, navigator_config.safety_radius)
            detection_time = time.perf_counter() - started
        while world.time < time_limit:
            trajectory.record(world.time, world.husky_pose, world.husky_velocity,
                              world.wanderer_positions)
            if forecast is not None:
                now = world.wanderer_positions
                grid.set_wanderers(forecast_positions(
                    now, forecast['previous'], world.time - forecast['time'],
                    world.husky_pose[:2], forecast['reach']))
                forecast.update(previous=now, time=world.time)
            elif oracle:
                grid.set_wanderers(world.wanderer_positions)
            if meter is not None:
                path = navigator.path
                path_labels = None if path is None else navigator.grid.labels[path[:, 0],
                                                                              path[:, 1]]
            pose = world.husky_pose
            if noise is not None:
                pose = tuple(np.asarray(pose, dtype=float) + noise[0].normal(0.0, noise[1]))
            out = navigator.step(world.time, pose, scan.ranges, scan.angle_min,
                                 scan.angle_increment, scan.range_min, scan.range_max)
            if meter is not None:
                started = time.perf_counter()
                measure_step(meter, navigator, world, scan, out, path, path_labels)
                detection_time += time.perf_counter() - started
            if recorder is not None:
                recorder(world, navigator)
            if (out.status is NavigatorStatus.GOAL_REACHED
                    or math.dist(world.husky_pose[:2], task.goal[:2]) <= GOAL_TOLERANCE):
                break
            scan = world.advance(out.command.linear, out.command.angular)
            travelled += math.dist(last_xy, world.husky_pose[:2])
            last_xy = world.husky_pose[:2]
        else:
            trajectory.record(world.time, world.husky_pose, world.husky_velocity,
                              world.wanderer_positions)
        contacts = world.contacts
        walls_mobile = ghosts = 0
        if navigator.grid is not None:
            walls_mobile, ghosts = map_quality(
                navigator.grid.labels, navigator.grid.geometry, scenario.occupied,
                scenario.geometry, world.wanderer_positions, world.wanderer_radius,
                navigator_config.safety_radius)
        end_time = world.time
    reported_goal = navigator.status is NavigatorStatus.GOAL_REACHED
    metrics = trajectory.metrics(task.goal, shortest, time_limit, travelled, contacts.events,
                                 reported_goal, navigator.status is NavigatorStatus.NO_PATH)
    reached = metrics.judged_success
    if contacts.events:
        failure = 'collision'
    elif reached:
        failure = ''
    elif navigator.status is NavigatorStatus.NO_PATH:
        failure = 'no_path'
    else:
        failure = 'timeout'
    return EpisodeResult(
        scenario=scenario.name, task=task_index, wanderers=wanderers, seed=seed,
        success=reached and not contacts.events, failure=failure, time=round(end_time, 3),
        time_limit=round(time_limit, 3), path_length=round(travelled, 3),
        shortest_path=round(shortest, 3), replans=navigator.replans,
        forgets=navigator.forgets,
        wall_contacts=contacts.wall_events, wanderer_contacts=contacts.wanderer_events,
        robot_caused_contacts=contacts.robot_caused_events,
        agent_caused_contacts=contacts.agent_caused_events,
        walls_labelled_mobile=walls_mobile, ghost_obstacles=ghosts,
        detection=None if meter is None else meter.result(), metrics=metrics,
        detection_wall_time=None if meter is None else round(detection_time, 3))


def measure_step(meter, navigator, world, scan, out, path, path_labels):
    """
    Feed one navigator step to a `DetectionMeter`, with the world's ground truth.

    Parameters
    ----------
    meter : DetectionMeter
        The episode's meter.
    navigator : Navigator
        After its step on ``scan``.
    world : sim_bridge.world.World
        At the scan's tick.
    scan : sim_bridge.laser.LaserScan
        The scan the navigator just folded in.
    out : NavigatorOutput
        The step's output.
    path, path_labels : ndarray or None
        The navigator's path before the step and the labels of its cells then.

    """
    wanderer_xy = world.wanderer_positions
    labels = navigator.grid.labels
    # The costmap is measured by its lethal cells, not their inflation (docs/detection.md).
    detected = (navigator.grid.lethal_labels() if isinstance(navigator.grid, CostmapGrid)
                else labels)
    hits = (np.zeros(0), np.zeros(0))
    if wanderer_xy.shape[0]:
        hits = wanderer_hit_points(compose(world.husky_pose, navigator.config.laser_offset),
                                   scan.ranges, scan.angle_min, scan.angle_increment,
                                   scan.range_min, scan.range_max, world.scan_wanderer_beams())
    meter.record_scan(detected, navigator.grid.last_window, wanderer_xy, hits)
    meter.record_replan(out.replan_cause, path, path_labels, labels, wanderer_xy)
