"""A stand-in for the simulator: /clock, odometry and scans of a robot in a room, by hand."""

import time

from builtin_interfaces.msg import Time
from dpn_navigator.ros.conversions import make_laser_scan, pose_to_odometry
from dpn_navigator.ros.qos import COMMAND_QOS, SENSOR_QOS
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
import numpy as np
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN, ray_cast
from sensor_msgs.msg import LaserScan

#: The robot's pose in the 12 m x 12 m room, facing a goal at (10, 6) [m, m, rad].
POSE = (2.0, 6.0, 0.0)


#: A robot whose driver publishes odometry and scans but no TF: scans are placed from
#: odometry at once (under ``pose_source: auto`` the first second would wait for TF).
BARE_ROBOT = Parameter('pose_source', value='odom')


def room_navigator(context, use_sim_time=True, *more_overrides):
    """
    Return a ``DpnNode`` for the 12 m x 12 m room with its goal at (10, 6) m.

    Its laser is at the base's centre (``laser_x`` 0), as in the scans of ``scan_scenes``;
    ``more_overrides`` (``Parameter``) set other parameters.

    """
    from dpn_navigator.ros.dpn_node import DpnNode
    overrides = [BARE_ROBOT,
                 Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
                 Parameter('use_default_goal', value=True),
                 Parameter('goal_x', value=10.0), Parameter('goal_y', value=6.0),
                 Parameter('laser_x', value=0.0),
                 Parameter('use_sim_time', value=use_sim_time), *more_overrides]
    return DpnNode(context=context, parameter_overrides=overrides)


class SimulatorStandIn(Node):
    """Publish /clock, odometry and scans as the simulator would; record the commands."""

    def __init__(self, context):
        super().__init__('simulator_stand_in', context=context)
        self.clock_pub = self.create_publisher(Clock, '/clock', COMMAND_QOS)
        self.odom_pub = self.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS)
        self.scan_pub = self.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS)
        self.commands = []          # (steady time [s], linear, angular)
        self.create_subscription(Twist, '/compabot/cmd_vel', self.on_cmd, COMMAND_QOS)
        self.sim_time = 1.0
        occupied = np.zeros((240, 240), dtype=bool)
        occupied[:6, :] = occupied[-6:, :] = occupied[:, :6] = occupied[:, -6:] = True
        self.ranges = ray_cast(occupied, POSE, 0.05, 10.0)

    def on_cmd(self, msg):
        self.commands.append((time.monotonic(), msg.linear.x, msg.angular.z))

    def tick(self, streams):
        """Advance simulated time by 20 ms and publish the given streams; return the time."""
        self.sim_time += 0.02
        stamp = Time(sec=int(self.sim_time), nanosec=int(self.sim_time % 1.0 * 1e9))
        if 'clock' in streams:
            self.clock_pub.publish(Clock(clock=stamp))
        if 'odometry' in streams:
            self.odom_pub.publish(pose_to_odometry(POSE, (0.0, 0.0), stamp))
        if 'scan' in streams:
            self.scan_pub.publish(make_laser_scan(self.ranges, ANGLE_MIN, ANGLE_INCREMENT,
                                                  RANGE_MIN, 10.0, stamp))
        return time.monotonic()
