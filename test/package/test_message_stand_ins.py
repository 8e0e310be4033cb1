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
