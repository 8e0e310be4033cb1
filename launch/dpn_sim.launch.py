"""
Start the pybullet world and the dpn navigator, with RViz on request.

``ros2 launch dpn_navigator dpn_sim.launch.py [gui:=true] [wanderers:=3] [rviz:=true]
[default_goal:=false] [namespace:=robot2]``

Parameters come from ``config/pybullet_world.yaml`` and ``config/dpn.yaml``; both nodes run on
the world's simulated ``/clock``, in the namespace ``namespace`` (default ``compabot``: topics
``/compabot/scan`` and so on). RViz shows ``config/dpn.rviz``: map, plan, markers, laser scan,
TF and the robot's base frame; the config names the ``/compabot/...`` topics, which the launch
file remaps into ``namespace`` (the *2D Goal Pose* tool's ``goal_pose`` too).
"""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution, TextSubstitution
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
from launch_ros.substitutions import FindPackageShare


#: The topics config/dpn.rviz names under /compabot, remapped into the launch namespace.
RVIZ_TOPICS = ('map', 'map_updates', 'marker', 'odom_real', 'plan', 'scan', 'sim/wanderers',
               'goal_pose')


def generate_launch_description():
    """Describe the two nodes, their parameter files and the optional RViz window."""
    config = PathJoinSubstitution([FindPackageShare('dpn_navigator'), 'config'])
    namespace = LaunchConfiguration('namespace')
    world = Node(
        package='sim_bridge', executable='pybullet_world', name='pybullet_world',
        namespace=namespace, output='screen',
        parameters=[
            PathJoinSubstitution([config, 'pybullet_world.yaml']),
            {'gui': ParameterValue(LaunchConfiguration('gui'), value_type=bool),
             'wanderers': ParameterValue(LaunchConfiguration('wanderers'), value_type=int),
             'scenario': LaunchConfiguration('scenario')},
        ])
    navigator = Node(
        package='dpn_navigator', executable='dpn', name='dpn', namespace=namespace,
        output='screen',
        parameters=[PathJoinSubstitution([config, 'dpn.yaml']),
                    {'use_sim_time': True,
                     'use_default_goal': ParameterValue(LaunchConfiguration('default_goal'),
                                                        value_type=bool)}])
    rviz = Node(
        package='rviz2', executable='rviz2', name='rviz2',
        arguments=['-d', PathJoinSubstitution([config, 'dpn.rviz'])],
        parameters=[{'use_sim_time': True}],
        remappings=[(f'/compabot/{topic}', [TextSubstitution(text='/'), namespace,
                                            TextSubstitution(text=f'/{topic}')])
                    for topic in RVIZ_TOPICS],
        condition=IfCondition(LaunchConfiguration('rviz')))
    return LaunchDescription([
        DeclareLaunchArgument('gui', default_value='false',
                              description='Open the pybullet GUI window.'),
        DeclareLaunchArgument('wanderers', default_value='3',
                              description='Number of wandering P3-AT robots, 0 to 10.'),
        DeclareLaunchArgument('scenario', default_value='back_and_forth',
                              description='Built-in scenario name or a map_server yaml path.'),
        DeclareLaunchArgument('rviz', default_value='false', description='Start RViz.'),
        DeclareLaunchArgument('namespace', default_value='compabot',
                              description='Namespace of both nodes and their topics (RViz '
                              'follows, its goal_pose too).'),
        DeclareLaunchArgument('default_goal', default_value='true',
                              description="Drive to dpn.yaml's goal_x, goal_y at start; false: "
                              'wait for a goal on goal_pose.'),
        world,
        navigator,
        rviz,
    ])
