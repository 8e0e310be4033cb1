"""
Names shared by the nodes: the default namespace, and the topics that stay global.

Every other topic name of the nodes is relative (``scan``, ``map``, ``cmd_vel``, ...), so it
resolves under the node's namespace: ``/compabot/scan`` by default, ``/robot2/scan`` with
``--ros-args -r __ns:=/robot2``.

"""

#: Namespace of both nodes when none is given on the command line or by a launch file, so that a
#: bare ``ros2 run`` keeps the topics of the design card (``/compabot/scan`` and so on).
DEFAULT_NAMESPACE = 'compabot'

#: Global by convention: tf2 listeners, RViz and rqt read these absolute names. With several
#: robots, remap them (``-r /tf:=tf -r /tf_static:=tf_static``, Nav2's multi-robot pattern) or
#: give each robot its own frame names.
TF_TOPIC = '/tf'
TF_STATIC_TOPIC = '/tf_static'
#: diagnostic_aggregator and rqt_robot_monitor read ``/diagnostics``; statuses carry the node's
#: fully qualified name, so robots stay apart on the one topic.
DIAGNOSTICS_TOPIC = '/diagnostics'
