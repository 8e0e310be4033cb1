"""Tests of the dpn node in one process: real topics over DDS, scans ray-cast in a room."""

import math
from pathlib import Path as FilePath
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from dpn_navigator.core.cell_label import CellLabel
from dpn_navigator.ros.conversions import (apply_occupancy_grid_update,
                                           labels_to_occupancy_grid, make_laser_scan,
                                           marker_points, occupancy_grid_values, pose_to_odometry)
from dpn_navigator.ros.dpn_node import DpnNode
from dpn_navigator.ros.qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS
from geometry_msgs.msg import PoseStamped, Twist, TwistStamped
from map_msgs.msg import OccupancyGridUpdate
from nav_msgs.msg import OccupancyGrid, Odometry, Path
from node_harness import executor_for, spin_until
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN, ray_cast
from sensor_msgs.msg import LaserScan
from sim_stand_in import BARE_ROBOT
from visualization_msgs.msg import MarkerArray

REPO = FilePath(__file__).resolve().parents[2]
RANGE_MAX = 10.0
POSE = (2.0, 6.0, 0.0)


def room():
    occupied = np.zeros((240, 240), dtype=bool)        # 12 m x 12 m at 5 cm
    occupied[:6, :] = occupied[-6:, :] = occupied[:, :6] = occupied[:, -6:] = True
    return occupied


class Probe(Node):
    """Publish what the dpn node listens to; record what it publishes."""

    def __init__(self, context, command_type=Twist):
        super().__init__('probe', context=context)
        self.scan_pub = self.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS)
        self.odom_pub = self.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS)
        self.goal_pub = self.create_publisher(PoseStamped, '/compabot/goal_pose', COMMAND_QOS)
        self.received = {'map': [], 'cmd': [], 'status': [], 'marker': []}
        topics = ((OccupancyGrid, '/compabot/map', 'map', LATCHED_QOS),
                  (command_type, '/compabot/cmd_vel', 'cmd', COMMAND_QOS),
                  (DiagnosticStatus, '/compabot/status', 'status', LATCHED_QOS),
                  (MarkerArray, '/compabot/marker', 'marker', LATCHED_QOS))
        for msg_type, topic, key, qos in topics:
            self.create_subscription(msg_type, topic, self.received[key].append, qos)

    def send(self, pose=POSE, scan=None, **scan_changes):
        stamp = self.get_clock().now().to_msg()
        self.odom_pub.publish(pose_to_odometry(pose, (0.0, 0.0), stamp))
        if scan is None:
            ranges = ray_cast(room(), pose, 0.05, RANGE_MAX)
            scan = make_laser_scan(ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX,
                                   stamp)
        for field, value in scan_changes.items():
            setattr(scan, field, value)
        self.scan_pub.publish(scan)

    def status_value(self, key):
        return {kv.key: kv.value for kv in self.received['status'][-1].values}[key]


@pytest.fixture
def nodes(ros_context):
    overrides = [BARE_ROBOT,
                 Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
                 Parameter('use_default_goal', value=True),
                 Parameter('goal_x', value=10.0), Parameter('goal_y', value=6.0),
                 Parameter('sensor_timeout', value=0.3), Parameter('laser_x', value=0.0)]
    dpn = DpnNode(context=ros_context, parameter_overrides=overrides)
    probe = Probe(ros_context)
    with executor_for(ros_context, dpn, probe) as executor:
        yield dpn, probe, executor


def wait_for_discovery(executor, probe):
    assert spin_until(executor, lambda: probe.scan_pub.get_subscription_count() > 0
                      and probe.odom_pub.get_subscription_count() > 0)


def test_scans_become_map_commands_markers_and_status(nodes):
    dpn, probe, executor = nodes
    # Every map the node publishes (refreshed in windows) equals a full conversion.
    same_as_full = []
    publish_map = dpn.map_pub.publish

    def checked_publish(msg):
        full = labels_to_occupancy_grid(dpn.navigator.grid.labels, 0.5, (0.0, 0.0),
                                        msg.header.stamp)
        same_as_full.append(msg.data == full.data)
        publish_map(msg)

    dpn.map_pub.publish = checked_publish
    wait_for_discovery(executor, probe)
    # Odometry first so that the scan can be placed, then a few scans.
    for _ in range(5):
        probe.send()
        spin_until(executor, lambda: False, timeout=0.05)
    assert spin_until(executor, lambda: probe.received['map'] and probe.received['cmd']
                      and probe.received['marker'])
    assert same_as_full and all(same_as_full)
    values = occupancy_grid_values(probe.received['map'][-1])
    assert values.shape == (24, 24)
    assert set(np.unique(values).tolist()) <= {-1, 0, 70, 100}
    assert np.count_nonzero(values == 0) > 50 and np.count_nonzero(values == 100) > 10
    moving = [cmd for cmd in probe.received['cmd'] if cmd.linear.x > 0.0]
    assert moving, 'the robot faces its goal in an open room: it should drive'
    for cmd in probe.received['cmd']:
        assert 0.0 <= cmd.linear.x <= 1.0 and abs(cmd.angular.z) <= 1.5
    planned = [m for m in probe.received['marker'][-1].markers if m.ns == 'planned_path']
    path = marker_points(planned[0])
    assert path.shape[0] >= 2
    assert np.allclose(path[-1], (10.0, 6.0))
    assert probe.status_value('status') == 'active'


def test_malformed_input_is_rejected_counted_and_survived(nodes):
    dpn, probe, executor = nodes
    wait_for_discovery(executor, probe)
    probe.send(angle_max=-2.0)                          # before odometry: still counted
    assert spin_until(executor, lambda: dpn.rejected['scan'] == 1)
    probe.send()
    assert spin_until(executor, lambda: dpn.pose is not None)
    probe.send(angle_max=0.5)                           # 640 ranges disagree with the angles
    probe.send(angle_increment=0.0)
    probe.send(range_max=0.05)                          # range_max <= range_min
    probe.send(angle_increment=math.nan)
    assert spin_until(executor, lambda: dpn.rejected['scan'] == 5)
    # Issue 32's crash: 2 beams, angle_min 0, angle_increment = angle_max = 1e-30 rad, twice
    # (the turn sweep read the first one's hits at the second).
    tiny_step = make_laser_scan(np.array([1.0, 1.0]), 0.0, 1e-30, RANGE_MIN, RANGE_MAX,
                                probe.get_clock().now().to_msg())
    tiny_step.angle_max = 1e-30
    probe.send(scan=tiny_step)
    probe.send(scan=tiny_step)
    assert spin_until(executor, lambda: dpn.rejected['scan'] == 7)
    bad_odom = pose_to_odometry((math.nan, 1.0, 0.0), (0.0, 0.0),
                                probe.get_clock().now().to_msg())
    probe.odom_pub.publish(bad_odom)
    off_map = PoseStamped()
    off_map.header.frame_id = 'map'
    off_map.pose.position.x = 1e5        # the map may grow, but not past map_memory_limit
    probe.goal_pub.publish(off_map)
    assert spin_until(executor, lambda: dpn.rejected['odometry'] == 1
                      and dpn.rejected['goal'] == 1)
    assert spin_until(executor, lambda: probe.received['status']
                      and probe.status_value('rejected_scans') == '7'
                      and probe.status_value('rejected_goals') == '1')
    assert dpn.navigator.goal == (10.0, 6.0)            # the bad goal did not replace it
    # Still alive: a good scan is mapped and answered.
    probe.received['map'].clear()
    probe.send()
    assert spin_until(executor, lambda: probe.received['map'])


def test_stale_sensors_stop_the_robot(nodes):
    dpn, probe, executor = nodes
    wait_for_discovery(executor, probe)
    deadline = time.monotonic() + 1.0
    while time.monotonic() < deadline:                   # a healthy stream at ~20 Hz
        probe.send()
        spin_until(executor, lambda: False, timeout=0.05)
    assert any(cmd.linear.x > 0.0 for cmd in probe.received['cmd'])
    probe.received['cmd'].clear()
    stopped_at = time.monotonic()
    assert spin_until(executor, lambda: probe.received['cmd']
                      and probe.received['cmd'][-1].linear.x == 0.0, timeout=3.0)
    # No moving command after the stream stopped beyond the timeout (0.3 s) plus a tick.
    assert time.monotonic() - stopped_at < 1.0
    assert spin_until(executor, lambda: probe.status_value('sensors_stale') == 'True')
    # The stream returns: commands resume.
    probe.received['cmd'].clear()
    for _ in range(4):
        probe.send()
        spin_until(executor, lambda: False, timeout=0.05)
    assert spin_until(executor, lambda: any(c.linear.x > 0.0 for c in probe.received['cmd']))


def test_plan_diagnostics_map_load_time_and_frame_checks(nodes):
    dpn, probe, executor = nodes
    plans, arrays = [], []
    probe.create_subscription(Path, '/compabot/plan', plans.append, LATCHED_QOS)
    probe.create_subscription(DiagnosticArray, '/diagnostics', arrays.append, COMMAND_QOS)
    wait_for_discovery(executor, probe)
    for _ in range(4):
        probe.send()
        spin_until(executor, lambda: False, timeout=0.05)
    assert spin_until(executor, lambda: plans and len(probe.received['map']) >= 2 and arrays)
    poses = plans[-1].poses
    assert plans[-1].header.frame_id == 'map' and len(poses) >= 2
    assert (poses[-1].pose.position.x, poses[-1].pose.position.y) == pytest.approx((10.0, 6.0))
    load_times = {(m.info.map_load_time.sec, m.info.map_load_time.nanosec)
                  for m in probe.received['map']}
    stamps = {(m.header.stamp.sec, m.header.stamp.nanosec) for m in probe.received['map']}
    assert len(load_times) == 1 and len(stamps) >= 2
    assert arrays[-1].status[0].name == '/compabot/dpn'
    # A scan in another frame than laser_frame is rejected and counted.
    probe.send(header=make_laser_scan(np.ones(640), ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN,
                                      RANGE_MAX, probe.get_clock().now().to_msg(),
                                      frame_id='base_scan').header)
    assert spin_until(executor, lambda: dpn.scan_frame_mismatches == 1)
    assert dpn.rejected['scan'] == 1
    # A goal in another frame is rejected; an empty frame means the map frame.
    goal = PoseStamped()
    goal.header.frame_id = 'odom'
    goal.pose.position.x, goal.pose.position.y = 3.0, 3.0
    probe.goal_pub.publish(goal)
    assert spin_until(executor, lambda: dpn.rejected['goal'] == 1)
    goal.header.frame_id = ''
    probe.goal_pub.publish(goal)
    assert spin_until(executor, lambda: dpn.navigator.goal == (3.0, 3.0))
    assert spin_until(executor, lambda: probe.status_value('scan_frame_mismatches') == '1')


def test_stamped_commands_integer_parameters_and_mobile_value(ros_context):
    overrides = [BARE_ROBOT, Parameter('map_width', value=12), Parameter('map_height', value=12),
                 Parameter('use_default_goal', value=True),
                 Parameter('goal_x', value=10), Parameter('goal_y', value=6.0),
                 Parameter('cmd_vel_stamped', value=True),
                 Parameter('map_mobile_value', value=99)]
    dpn = DpnNode(context=ros_context, parameter_overrides=overrides)
    assert (dpn.params.navigator.width, dpn.params.goal) == (12.0, (10.0, 6.0))
    assert isinstance(dpn.params.navigator.width, float)
    probe = Probe(ros_context, command_type=TwistStamped)
    stamped = probe.received['cmd']
    with executor_for(ros_context, dpn, probe) as executor:
        wait_for_discovery(executor, probe)
        for _ in range(4):
            probe.send()
            spin_until(executor, lambda: False, timeout=0.05)
        assert spin_until(executor, lambda: stamped and probe.received['map'])
        assert any(cmd.twist.linear.x > 0.0 for cmd in stamped)
        # The sensors stop: the watchdog's zero commands are stamped too.
        assert spin_until(executor, lambda: dpn.stale and stamped[-1].twist.linear.x == 0.0)
    assert stamped[-1].header.frame_id == 'base_link'
    assert (stamped[-1].twist.linear.x, stamped[-1].twist.angular.z) == (0.0, 0.0)
    dpn.navigator.grid.labels[0, 0] = CellLabel.MOBILE_OBSTACLE
    grid = labels_to_occupancy_grid(dpn.navigator.grid.labels, 0.5, (0.0, 0.0),
                                    probe.get_clock().now().to_msg(),
                                    mobile_value=dpn.params.map_mobile_value)
    assert occupancy_grid_values(grid)[0, 0] == 99


@pytest.mark.parametrize('updates', [True, False])
def test_between_full_maps_the_changed_cells_go_out_as_updates(ros_context, updates):
    overrides = [BARE_ROBOT,
                 Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
                 Parameter('use_default_goal', value=True),
                 Parameter('goal_x', value=10.0), Parameter('goal_y', value=6.0),
                 Parameter('laser_x', value=0.0), Parameter('map_publish_period', value=60.0),
                 Parameter('map_updates', value=updates)]
    dpn = DpnNode(context=ros_context, parameter_overrides=overrides)
    probe = Probe(ros_context)
    received = []
    probe.create_subscription(OccupancyGridUpdate, '/compabot/map_updates', received.append,
                              COMMAND_QOS)
    with executor_for(ros_context, dpn, probe) as executor:
        wait_for_discovery(executor, probe)
        # The robot drives through the room: every scan changes some cells.
        for step in range(8):
            probe.send(pose=(2.0 + 0.5 * step, 6.0 - 0.3 * step, 0.1 * step))
            spin_until(executor, lambda: False, timeout=0.05)
        assert spin_until(executor, lambda: probe.received['map'])
        if updates:
            assert spin_until(executor, lambda: len(received) >= 3)
        else:
            spin_until(executor, lambda: False, timeout=0.5)
    assert len(probe.received['map']) == 1            # one full map within the 60 s
    assert (len(received) > 0) == updates
    values = occupancy_grid_values(probe.received['map'][0]).copy()
    for update in received:
        assert update.header.frame_id == 'map'
        apply_occupancy_grid_update(values, update)
    now = occupancy_grid_values(labels_to_occupancy_grid(
        dpn.navigator.grid.labels, 0.5, (0.0, 0.0), probe.get_clock().now().to_msg()))
    # With the updates, the subscriber holds the node's map; without them, the first one.
    assert np.array_equal(values, now) == updates


@pytest.mark.parametrize('exclusive', [True, False])
def test_track_rules_reach_the_navigators_tracks(ros_context, exclusive):
    overrides = [BARE_ROBOT,
                 Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
                 Parameter('track_exclusive', value=exclusive),
                 Parameter('track_still_distance', value=0.05),
                 Parameter('object_min_hits', value=4),
                 Parameter('fine_evidence_resolution', value=0.05),
                 Parameter('fine_evidence_radius', value=0.25),
                 Parameter('object_memory_short_segments', value=not exclusive)]
    dpn = DpnNode(context=ros_context, parameter_overrides=overrides)
    try:
        assert dpn.navigator.grid.tracks.config.exclusive is exclusive
        assert dpn.navigator.grid.tracks.config.still_distance == 0.05
        assert dpn.navigator.grid.tracks.config.min_hits == 4
        assert dpn.navigator.grid.rule.object_min_hits == 4
        assert dpn.navigator.grid.rule.object_memory_short_segments is (not exclusive)
        fine = dpn.navigator.grid.fine_evidence
        assert fine.geometry.resolution == 0.05 and fine.radius == 0.25
    finally:
        dpn.destroy_node()


@pytest.mark.parametrize('value, match', [
    ('abc', 'map_width must be a number'),
    (0, r'map_width = 0.0 is outside \[0.1'),
])
def test_bad_number_parameters_get_a_one_line_error(ros_context, value, match):
    with pytest.raises(ValueError, match=match):
        DpnNode(context=ros_context, parameter_overrides=[Parameter('map_width', value=value)])


def test_two_namespaced_navigators_do_not_hear_each_other(ros_context):
    config = str(REPO / 'config' / 'dpn.yaml')
    pair = [DpnNode(context=ros_context, cli_args=[
        '--ros-args', '-r', f'__ns:=/{ns}', '--params-file', config,
        '-p', 'map_width:=12.0', '-p', 'map_height:=12.0', '-p', 'use_default_goal:=true',
        '-p', 'goal_x:=10.0', '-p', 'goal_y:=6.0', '-p', 'laser_x:=0.0',
        '-p', 'pose_source:=odom'])
        for ns in ('robot1', 'robot2')]
    # The /**/dpn key of the params file still applies in a namespace.
    assert all(n.params.navigator.resolution == 0.5 and n.params.map_frame == 'map'
               for n in pair)
    assert [n.get_fully_qualified_name() for n in pair] == ['/robot1/dpn', '/robot2/dpn']
    probe = Node('pair_probe', context=ros_context)
    scan_pub = probe.create_publisher(LaserScan, '/robot1/scan', SENSOR_QOS)
    odom_pub = probe.create_publisher(Odometry, '/robot1/odom', SENSOR_QOS)
    maps = {'robot1': [], 'robot2': [], 'compabot': []}
    for ns, received in maps.items():
        probe.create_subscription(OccupancyGrid, f'/{ns}/map', received.append, LATCHED_QOS)
    with executor_for(ros_context, *pair, probe) as executor:
        assert spin_until(executor, lambda: scan_pub.get_subscription_count() == 1
                          and odom_pub.get_subscription_count() == 1)
        for _ in range(4):
            stamp = probe.get_clock().now().to_msg()
            odom_pub.publish(pose_to_odometry(POSE, (0.0, 0.0), stamp))
            scan_pub.publish(make_laser_scan(ray_cast(room(), POSE, 0.05, RANGE_MAX),
                                             ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX,
                                             stamp))
            spin_until(executor, lambda: False, timeout=0.05)
        assert spin_until(executor, lambda: maps['robot1'])
        spin_until(executor, lambda: False, timeout=0.5)
        topics = {name for name, _ in probe.get_publisher_names_and_types_by_node(
            'dpn', '/robot2')}
    assert {'/robot2/map', '/robot2/cmd_vel', '/robot2/plan', '/robot2/status'} <= topics
    assert pair[0].pose is not None and pair[1].pose is None
    assert not maps['robot2'] and not maps['compabot']
    assert pair[1].navigator.grid.labels.max() == CellLabel.NON_EXPLORED


def laser_placement(x, ranges):
    """Return a placed scan of ``ranges`` [m] from a laser at (``x``, 1) [m]."""
    from dpn_navigator.ros.scan_placement import ScanPlacement
    fields = {'ranges': np.asarray(ranges, dtype=np.float32), 'angle_min': ANGLE_MIN,
              'angle_increment': ANGLE_INCREMENT, 'angle_max': -ANGLE_MIN,
              'range_min': RANGE_MIN, 'range_max': 30.0}
    return ScanPlacement((x, 1.0, 0.0), (x + 0.3, 1.0, 0.0), fields, 'odom')


SWITCH_OFF = Parameter('real_laser_switch', value=0.0)


@pytest.mark.parametrize('moving, overrides, lost, hints', [
    (True, [SWITCH_OFF], True, 1),                              # dpn.yaml with a real laser
    (True, [], True, 0),                                        # the navigator switches itself
    (True, [SWITCH_OFF], False, 0),                             # an ideal laser, open space
    (False, [SWITCH_OFF], True, 0),                             # waiting for a goal: no word
    (True, [SWITCH_OFF, Parameter('no_return_reach', value=0.0)], True, 0),  # the real rule
])
def test_a_laser_losing_returns_on_the_move_gets_one_hint(ros_context, moving, overrides,
                                                          lost, hints):
    from dpn_navigator.recording.sensor_survey import NODE_HINT_SCANS
    dpn = DpnNode(context=ros_context, parameter_overrides=[BARE_ROBOT, *overrides])
    try:
        ranges = np.full(640, 4.0)
        if lost:
            ranges[::5] = np.inf                                # 20 % lost inside a wall
        else:
            ranges[:128] = np.inf                               # 20 % open space
        for index in range(NODE_HINT_SCANS + 20):
            dpn.survey_laser(laser_placement(0.02 * index if moving else 0.0, ranges))
        assert dpn.laser_hints == hints
        # Surveyed until the hints are given, never after; standing, still surveying.
        assert (dpn.laser_survey is None) is moving
    finally:
        dpn.destroy_node()


def test_the_real_laser_switch_is_logged_once_and_in_the_status(ros_context, capfd):
    dpn = DpnNode(context=ros_context, parameter_overrides=[BARE_ROBOT])
    try:
        ranges = np.full(640, 4.0)
        ranges[::5] = np.inf                                    # 20 % lost inside a wall
        for index in range(6):
            placement = laser_placement(0.04 * index, ranges)
            dpn.navigator.observe(placement.base_pose, **placement.fields, stamp=10.0 + index,
                                  laser_pose=placement.laser_pose)
            dpn.report_real_laser(10.0 + index)
        assert dpn.navigator.real_laser.switched_at == 13.0     # 0.12 m from the start
        assert dpn.navigator.config.no_return_reach == 0.0      # from the next scan on
        assert dpn.real_laser_since == 14.0
        status = {kv.key: kv.value for kv in dpn.diagnostics.last.values}
        assert status['real_laser_since'] == '14.000'
        err = capfd.readouterr().err
        assert err.count('laser: a real laser: once it moved') == 1
        assert 'from 4.0 s on' in err and 'no_return_reach 0' in err
    finally:
        dpn.destroy_node()
