"""
Start the pybullet world and the dpn navigator, with RViz on request.

``ros2 launch dpn_navigator dpn_sim.launch.py [gui:=true] [wanderers:=3] [rviz:=true]
[default_goal:=false]``

Parameters come from ``config/pybullet_world.yaml`` and ``config/dpn.yaml``; both nodes run on
the world's simulated ``/clock``, in their default namespace ``compabot`` (topics
``/compabot/scan`` and so on). RViz shows ``config/dpn.rviz``: map, plan, markers, laser scan,
TF and the robot's base frame.
"""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    """Describe the two nodes, their parameter files and the optional RViz window."""
    config = PathJoinSubstitution([FindPackageShare('dpn_navigator'), 'config'])
    world = Node(
        package='sim_bridge', executable='pybullet_world', name='pybullet_world',
        output='screen',
        parameters=[
            PathJoinSubstitution([config, 'pybullet_world.yaml']),
            {'gui': ParameterValue(LaunchConfiguration('gui'), value_type=bool),
             'wanderers': ParameterValue(LaunchConfiguration('wanderers'), value_type=int),
             'scenario': LaunchConfiguration('scenario')},
        ])
    navigator = Node(
        package='dpn_navigator', executable='dpn', name='dpn', output='screen',
        parameters=[PathJoinSubstitution([config, 'dpn.yaml']),
                    {'use_sim_time': True,
                     'use_default_goal': ParameterValue(LaunchConfiguration('default_goal'),
                                                        value_type=bool)}])
    rviz = Node(
        package='rviz2', executable='rviz2', name='rviz2',
        arguments=['-d', PathJoinSubstitution([config, 'dpn.rviz'])],
        parameters=[{'use_sim_time': True}],
        condition=IfCondition(LaunchConfiguration('rviz')))
    return LaunchDescription([
        DeclareLaunchArgument('gui', default_value='false',
                              description='Open the pybullet GUI window.'),
        DeclareLaunchArgument('wanderers', default_value='3',
                              description='Number of wandering P3-AT robots, 0 to 10.'),
        DeclareLaunchArgument('scenario', default_value='back_and_forth',
                              description='Built-in scenario name or a map_server yaml path.'),
        DeclareLaunchArgument('rviz', default_value='false', description='Start RViz.'),
        DeclareLaunchArgument('default_goal', default_value='true',
                              description="Drive to dpn.yaml's goal_x, goal_y at start; false: "
                              'wait for a goal on goal_pose.'),
        world,
        navigator,
        rviz,
    ])
