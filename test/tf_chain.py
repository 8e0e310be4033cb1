"""
A tiny TF buffer for tests (tf2_ros is not on PyPI): record TFMessages, resolve a chain.

Transforms are kept per child frame with their stamps; a lookup walks from the source frame up
to the target frame, taking for each dynamic link the transform stamped exactly at the asked
time (the world stamps odometry, TF and scans on one simulated clock) and for each static link
the latest one. Poses compose in 3D with quaternions.
"""

import numpy as np


def _rotate(q, v):
    x, y, z, w = q
    u = np.array([x, y, z])
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


def _multiply(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw,
                     aw * bw - ax * bx - ay * by - az * bz])


def _stamp_ns(stamp):
    return stamp.sec * 1_000_000_000 + stamp.nanosec


class FrameChain:
    """Transforms seen on ``/tf`` and ``/tf_static``, by child frame."""

    def __init__(self):
        self.parents = {}       # child -> parent
        self.dynamic = {}       # child -> {stamp [ns]: (translation, rotation)}
        self.static = {}        # child -> (translation, rotation)

    def add(self, msg, static):
        """Record every transform of a ``TFMessage``."""
        for t in msg.transforms:
            tr, rot = t.transform.translation, t.transform.rotation
            value = (np.array([tr.x, tr.y, tr.z]), np.array([rot.x, rot.y, rot.z, rot.w]))
            previous = self.parents.setdefault(t.child_frame_id, t.header.frame_id)
            assert previous == t.header.frame_id, f'{t.child_frame_id} has two parents'
            if static:
                self.static[t.child_frame_id] = value
            else:
                self.dynamic.setdefault(t.child_frame_id, {})[_stamp_ns(t.header.stamp)] = value

    def lookup(self, target, source, stamp):
        """
        Return ``(translation, quaternion xyzw)`` of ``source`` in ``target`` at ``stamp``.

        Raises
        ------
        LookupError
            When a link is missing, or a dynamic link has no transform at ``stamp``.

        """
        translation, rotation = np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0])
        frame, at = source, _stamp_ns(stamp)
        while frame != target:
            if frame not in self.parents:
                raise LookupError(f'no transform from {frame!r} towards {target!r}')
            if frame in self.static:
                link = self.static[frame]
            elif at in self.dynamic.get(frame, {}):
                link = self.dynamic[frame][at]
            else:
                raise LookupError(f'no transform of {frame!r} at {at} ns')
            # parent <- frame, then frame <- source so far.
            translation = link[0] + _rotate(link[1], translation)
            rotation = _multiply(link[1], rotation)
            frame = self.parents[frame]
        return translation, rotation
