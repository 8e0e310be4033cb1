"""
Coordinate frames in 3-D: rigid transforms and a TF buffer with tf2's rules, no ROS.

`Transform3D` is a rigid transform (translation and unit quaternion); `TfBuffer` stores the
transforms of a TF tree over time and looks one frame up in another, as tf2's ``BufferCore``
does, for tools that read bags and for nodes with no ``tf2_ros``.

"""

from .tf_buffer import (ConnectivityError, DEFAULT_CACHE_DURATION_NS, ExtrapolationError,
                        FrameLookupError, InvalidTransformError, TfBuffer, TransformError)
from .transform3d import Transform3D

__all__ = [
    'ConnectivityError', 'DEFAULT_CACHE_DURATION_NS', 'ExtrapolationError', 'FrameLookupError',
    'InvalidTransformError', 'TfBuffer', 'Transform3D', 'TransformError',
]
