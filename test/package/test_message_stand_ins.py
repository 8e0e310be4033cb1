"""
The message stand-ins in use are the standard messages, whichever way they were installed.

They are ``tf2_msgs/msg/TFMessage`` and ``map_msgs/msg/OccupancyGridUpdate``.

On an apt Jazzy install they are the real tf2_msgs and map_msgs; on the PyPI path they are the
one-message stand-ins that ``make setup`` builds from fallback/ into .venv. Either way the
TFMessage's RIHS01 type hash must be the one a Jazzy system announces for ``/tf`` (as ``ros2
topic info -v /tf`` prints it), or rclpy would not match it with tf2_ros, RViz and Nav2
publishers and subscribers; the OccupancyGridUpdate's definition must be the standard one,
which fixes its hash the same way.
"""

from pathlib import Path

from dpn_navigator.ros.qos import TF_QOS
from rclpy.node import Node
from tf2_msgs.msg import TFMessage

#: ``Topic type hash`` of ``/tf`` on ROS 2 Jazzy (tf2_msgs 0.36).
JAZZY_TF_MESSAGE_HASH = 'RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087'


def test_tf_message_has_the_jazzy_type_hash(ros_context):
    node = Node('tf_hash_probe', context=ros_context)
    try:
        node.create_publisher(TFMessage, '/tf', TF_QOS)
        (info,) = node.get_publishers_info_by_topic('/tf')
        assert info.topic_type == 'tf2_msgs/msg/TFMessage'
        assert str(info.topic_type_hash) == JAZZY_TF_MESSAGE_HASH
    finally:
        node.destroy_node()


def test_tf_message_carries_transforms():
    msg = TFMessage()
    assert list(msg.get_fields_and_field_types()) == ['transforms']
    assert msg.get_fields_and_field_types()['transforms'] == \
        'sequence<geometry_msgs/TransformStamped>'


def test_the_stand_in_is_hidden_from_colcon_and_keeps_the_standard_definition():
    fallback = Path(__file__).resolve().parents[2] / 'fallback'
    # colcon (and rosdep) never crawl it, so an apt Jazzy workspace uses the real tf2_msgs.
    assert (fallback / 'COLCON_IGNORE').is_file()
    definition = (fallback / 'tf2_msgs' / 'msg' / 'TFMessage.msg').read_text()
    assert definition.split() == ['geometry_msgs/TransformStamped[]', 'transforms']


def test_the_map_msgs_stand_in_keeps_the_standard_definition():
    # map_msgs/OccupancyGridUpdate (navigation_msgs), the type of the dpn node's map_updates.
    from map_msgs.msg import OccupancyGridUpdate
    assert OccupancyGridUpdate.get_fields_and_field_types() == {
        'header': 'std_msgs/Header', 'x': 'int32', 'y': 'int32', 'width': 'uint32',
        'height': 'uint32', 'data': 'sequence<int8>'}
    fallback = Path(__file__).resolve().parents[2] / 'fallback'
    definition = (fallback / 'map_msgs' / 'msg' / 'OccupancyGridUpdate.msg').read_text()
    assert definition.split() == ['std_msgs/Header', 'header', 'int32', 'x', 'int32', 'y',
                                  'uint32', 'width', 'uint32', 'height', 'int8[]', 'data']


#: RIHS01 hash of ``nav2_msgs/action/NavigateToPose`` from Nav2's jazzy definition, as rosidl
#: computes it here (the stand-in's ``share/nav2_msgs/action/NavigateToPose.json``); the fields
#: alone fix it, so the real nav2_msgs 1.3 has the same (not compared with an apt system).
NAVIGATE_TO_POSE_HASH = 'RIHS01_a56dba8a3234a1215e610180dc703ae25bbf406dded8b54887891c9732857eab'


def test_the_nav2_msgs_stand_in_keeps_the_standard_navigate_to_pose():
    import json
    # package.xml depends on nav2_msgs; on the PyPI path `make setup` builds the stand-in, so
    # its absence is a failure here, not a skip.
    from nav2_msgs.action import NavigateToPose
    assert NavigateToPose.Goal.get_fields_and_field_types() == {
        'pose': 'geometry_msgs/PoseStamped', 'behavior_tree': 'string'}
    assert NavigateToPose.Result.get_fields_and_field_types() == {
        'error_code': 'uint16', 'error_msg': 'string'}
    assert NavigateToPose.Feedback.get_fields_and_field_types() == {
        'current_pose': 'geometry_msgs/PoseStamped',
        'navigation_time': 'builtin_interfaces/Duration',
        'estimated_time_remaining': 'builtin_interfaces/Duration',
        'number_of_recoveries': 'int16', 'distance_remaining': 'float'}
    import sys
    from ament_index_python.packages import get_package_share_directory
    try:
        share = Path(get_package_share_directory('nav2_msgs'))
    except (OSError, LookupError):          # the PyPI path: .venv is the prefix, unsourced
        share = Path(sys.prefix) / 'share' / 'nav2_msgs'
    description = share / 'action' / 'NavigateToPose.json'
    hashes = {h['type_name']: h['hash_string']
              for h in json.loads(description.read_text())['type_hashes']}
    assert hashes['nav2_msgs/action/NavigateToPose'] == NAVIGATE_TO_POSE_HASH
    fallback = Path(__file__).resolve().parents[2] / 'fallback' / 'nav2_msgs'
    definition = (fallback / 'action' / 'NavigateToPose.action').read_text()
    fields = [line.split('#')[0].split() for line in definition.splitlines()]
    assert [f for f in fields if f] == [
        ['geometry_msgs/PoseStamped', 'pose'], ['string', 'behavior_tree'], ['---'],
        ['uint16', 'NONE=0'], ['uint16', 'error_code'], ['string', 'error_msg'], ['---'],
        ['geometry_msgs/PoseStamped', 'current_pose'],
        ['builtin_interfaces/Duration', 'navigation_time'],
        ['builtin_interfaces/Duration', 'estimated_time_remaining'],
        ['int16', 'number_of_recoveries'], ['float32', 'distance_remaining']]
