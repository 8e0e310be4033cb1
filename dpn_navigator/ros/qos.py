"""Quality-of-service profiles, chosen by meaning and named once for every node here."""

from rclpy.qos import (DurabilityPolicy, HistoryPolicy, qos_profile_sensor_data, QoSProfile,
                       ReliabilityPolicy)

#: Sensor streams (scan, odometry) as subscribed: best effort, keep the newest few.
SENSOR_QOS = qos_profile_sensor_data

#: Sensor streams as published (REP 2003): reliable, volatile, depth 10 (the system default),
#: so that reliable subscribers (Nav2's odometry smoother, `ros2 topic echo`) get them too and
#: best-effort ones still match.
SENSOR_PUBLISHER_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                                  reliability=ReliabilityPolicy.RELIABLE,
                                  durability=DurabilityPolicy.VOLATILE)

#: Latched state (map, markers, status): reliable, transient local, depth 1, like map_server and
#: slam_toolbox, so a late subscriber such as RViz gets the last message.
LATCHED_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                         reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)

#: Commands and goals: reliable, volatile.
COMMAND_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                         reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.VOLATILE)

#: ``/tf``: reliable, volatile, depth 100, as tf2_ros's ``DynamicBroadcasterQoS``.
TF_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                    reliability=ReliabilityPolicy.RELIABLE,
                    durability=DurabilityPolicy.VOLATILE)

#: ``/tf_static``: reliable, transient local, depth 1, as tf2_ros's ``StaticBroadcasterQoS``;
#: every static transform of a publisher goes in its one latched message.
TF_STATIC_QOS = LATCHED_QOS
