"""
The wanderers' ground truth as ``visualization_msgs/MarkerArray``: one cylinder per P3-AT.

Published by the ``pybullet_world`` node on ``sim/wanderers`` and written into the benchmark's
episode bags, so that RViz and Foxglove show where the other robots really are.

"""

import numpy as np
from visualization_msgs.msg import Marker, MarkerArray

#: Height of a Pioneer P3-AT [m].
P3AT_HEIGHT = 0.277
#: Colour of the wanderers (red, slightly transparent), RGBA in [0, 1].
WANDERER_RGBA = (0.9, 0.2, 0.2, 0.9)


def wanderer_markers(positions, radius, stamp, frame_id='map'):
    """
    Build one ``CYLINDER`` marker per wanderer at its true position.

    Parameters
    ----------
    positions : (K, 2) array_like of float
        Wanderer positions in ``frame_id`` [m]; K may be 0 (an empty array).
    radius : float
        Their circumscribed radius [m].
    stamp : builtin_interfaces.msg.Time
        Stamp of every marker.
    frame_id : str
        Frame of the positions.

    Returns
    -------
    MarkerArray
        Marker ``k`` (namespace ``wanderers``) is wanderer ``k``.

    """
    markers = MarkerArray()
    diameter = 2.0 * float(radius)
    rows = np.asarray(positions, dtype=np.float64).reshape(-1, 2).tolist()
    for index, (x, y) in enumerate(rows):
        marker = Marker()
        marker.header.stamp = stamp
        marker.header.frame_id = frame_id
        marker.ns = 'wanderers'
        marker.id = index
        marker.type = Marker.CYLINDER
        marker.action = Marker.ADD
        marker.pose.position.x, marker.pose.position.y = x, y
        marker.pose.position.z = P3AT_HEIGHT / 2.0
        marker.pose.orientation.w = 1.0
        marker.scale.x = marker.scale.y = diameter
        marker.scale.z = P3AT_HEIGHT
        marker.color.r, marker.color.g, marker.color.b, marker.color.a = WANDERER_RGBA
        markers.markers.append(marker)
    return markers
