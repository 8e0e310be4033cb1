"""
Hypothesis strategies for every field of the messages the nodes take in.

Floats mix the values that break code (NaN, infinities, +-DBL_MAX, +-9e307, float32 extremes,
tiny and negative values) with ordinary ones; integers cover each field's whole type range. A
message is either fully random or a valid one with one field broken, so that the navigator's
map, planner and follower are exercised as well as its rejections.
"""

import math

from builtin_interfaces.msg import Time
from geometry_msgs.msg import PoseStamped, Quaternion, Twist
from hypothesis import strategies as st
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan

FLOAT32_MAX = 3.4028234663852886e38
DBL_MAX = 1.7976931348623157e308
NASTY_FLOATS = (math.nan, math.inf, -math.inf, DBL_MAX, -DBL_MAX, 9e307, -9e307, FLOAT32_MAX,
                -FLOAT32_MAX, 1e-300, -1e-300, 0.0, -0.0, 1e9, -1e9, 1e6)
INT32 = st.integers(-2**31, 2**31 - 1)
UINT32 = st.integers(0, 2**32 - 1)

#: Any float64, weighted toward the values that break code.
any_float = st.one_of(st.sampled_from(NASTY_FLOATS), st.floats(allow_nan=True),
                      st.floats(-100.0, 100.0))
#: Any float32 (a float64 field of the message may hold more than this).
any_float32 = st.one_of(st.sampled_from((math.nan, math.inf, -math.inf, FLOAT32_MAX,
                                         -FLOAT32_MAX, 0.0, -0.0, 1e-38)),
                        st.floats(width=32), st.floats(-50.0, 50.0, width=32))
text = st.one_of(st.sampled_from(('', 'map', 'laser', 'odom', 'base_link')),
                 st.text(max_size=20))


@st.composite
def stamps(draw):
    """Return any ``builtin_interfaces/Time``: negative seconds, nanoseconds past 1e9."""
    return Time(sec=draw(INT32), nanosec=draw(UINT32))


@st.composite
def clocks(draw):
    """Return any ``rosgraph_msgs/Clock``."""
    return Clock(clock=draw(stamps()))


@st.composite
def quaternions(draw):
    """Return any orientation: unit, scaled, zero, huge, non-finite."""
    kind = draw(st.sampled_from(('unit', 'scaled', 'random')))
    if kind == 'random':
        return Quaternion(x=draw(any_float), y=draw(any_float), z=draw(any_float),
                          w=draw(any_float))
    yaw = draw(st.floats(-math.pi, math.pi))
    scale = 1.0 if kind == 'unit' else draw(st.sampled_from((2.0, 0.5, 1e-3, 1e154, 1e200,
                                                             DBL_MAX, 1.004)))
    return Quaternion(x=0.0, y=0.0, z=scale * math.sin(yaw / 2.0),
                      w=scale * math.cos(yaw / 2.0))


@st.composite
def odometries(draw, near=(6.0, 6.0)):
    """Return any ``nav_msgs/Odometry``, often a plausible pose near ``near`` [m]."""
    msg = Odometry()
    msg.header.stamp = draw(stamps())
    msg.header.frame_id = draw(text)
    msg.child_frame_id = draw(text)
    plausible = draw(st.booleans())
    position = msg.pose.pose.position
    if plausible:
        position.x = near[0] + draw(st.floats(-5.0, 5.0))
        position.y = near[1] + draw(st.floats(-5.0, 5.0))
    else:
        position.x, position.y = draw(any_float), draw(any_float)
    position.z = draw(any_float)
    msg.pose.pose.orientation = draw(quaternions())
    msg.pose.covariance = [draw(any_float) for _ in range(36)] if draw(st.booleans()) else \
        [0.0] * 36
    twist = msg.twist.twist
    twist.linear.x, twist.linear.y, twist.linear.z = (draw(any_float) for _ in range(3))
    twist.angular.x, twist.angular.y, twist.angular.z = (draw(any_float) for _ in range(3))
    return msg


@st.composite
def laser_scans(draw):
    """Return any ``sensor_msgs/LaserScan``: a valid 180-degree scan with fields broken."""
    msg = LaserScan()
    msg.header.stamp = draw(stamps())
    # Mostly the node's laser_frame, so that the fields behind the frame check are reached.
    msg.header.frame_id = draw(st.one_of(st.just('laser'), text))
    beams = draw(st.sampled_from((0, 1, 2, 17, 181, 640)))
    msg.angle_min = -math.pi / 2
    msg.angle_increment = math.pi / max(1, beams - 1)
    msg.angle_max = msg.angle_min + (beams - 1) * msg.angle_increment
    msg.range_min, msg.range_max = 0.1, 10.0
    ranges = draw(st.lists(any_float32, min_size=beams, max_size=beams)) \
        if draw(st.booleans()) else [draw(st.floats(0.0, 12.0, width=32))] * beams
    msg.ranges = ranges
    msg.intensities = draw(st.lists(any_float32, max_size=4))
    for name in draw(st.sets(st.sampled_from(('angle_min', 'angle_max', 'angle_increment',
                                              'time_increment', 'scan_time', 'range_min',
                                              'range_max')), max_size=3)):
        setattr(msg, name, draw(any_float32))
    return msg


@st.composite
def goals(draw):
    """Return any ``geometry_msgs/PoseStamped`` goal."""
    msg = PoseStamped()
    msg.header.stamp = draw(stamps())
    msg.header.frame_id = draw(text)
    position = msg.pose.position
    position.x, position.y, position.z = (draw(any_float) for _ in range(3))
    if draw(st.booleans()):
        position.x, position.y = draw(st.floats(-2.0, 14.0)), draw(st.floats(-2.0, 14.0))
    msg.pose.orientation = draw(quaternions())
    return msg


@st.composite
def twists(draw):
    """Return any ``geometry_msgs/Twist``."""
    msg = Twist()
    msg.linear.x, msg.linear.y, msg.linear.z = (draw(any_float) for _ in range(3))
    msg.angular.x, msg.angular.y, msg.angular.z = (draw(any_float) for _ in range(3))
    return msg


#: One message for the dpn node, tagged with its topic.
dpn_messages = st.one_of(st.tuples(st.just('scan'), laser_scans()),
                         st.tuples(st.just('odometry'), odometries()),
                         st.tuples(st.just('goal'), goals()),
                         st.tuples(st.just('clock'), clocks()))
