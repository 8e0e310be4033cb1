"""
Rigid transforms in 3-D: a translation and a unit quaternion, as ``geometry_msgs/Transform``.

A `Transform3D` ``T_ab`` places frame ``b`` in frame ``a``: it maps a point given in ``b`` to
``a``, ``p_a = R p_b + t``, and ``T_ab @ T_bc == T_ac``. Quaternions are ``(x, y, z, w)``,
the order of ``geometry_msgs/Quaternion`` and tf2. Roll, pitch and yaw are tf2's
``Matrix3x3::getRPY``: ``R = Rz(yaw) Ry(pitch) Rx(roll)`` (fixed axes x, y, z).

"""

import math

import numpy as np

#: Accepted deviation of a quaternion's squared norm from 1 (tf2's
#: ``QUATERNION_NORMALIZATION_TOLERANCE`` in ``buffer_core.cpp``); within it a quaternion is
#: normalised, beyond it rejected.
QUATERNION_NORM_TOLERANCE = 1e-2


def unit_quaternion(rotation):
    """
    Check and normalise a quaternion.

    Parameters
    ----------
    rotation : sequence of 4 float
        ``(x, y, z, w)``.

    Returns
    -------
    (4,) ndarray of float64
        The quaternion scaled to unit length.

    Raises
    ------
    ValueError
        When it has not 4 components, a non-finite one, or a squared norm farther than
        `QUATERNION_NORM_TOLERANCE` from 1 (tf2 ignores such a transform as
        ``TF_DENORMALIZED_QUATERNION``).

    """
    return np.array(_unit_quaternion(rotation))


def _floats(values, count, what):
    """Return ``values`` as a tuple of ``count`` floats; ValueError for another shape."""
    try:
        result = tuple(float(v) for v in values)
    except (TypeError, ValueError):
        result = None
    if result is None or len(result) != count:
        shape = np.shape(values)
        raise ValueError(f'{what}, got shape {shape}: {values!r}')
    return result


def _unit_quaternion(rotation):
    """`unit_quaternion` as a tuple of floats."""
    q = _floats(rotation, 4, 'a quaternion has 4 components (x, y, z, w)')
    if not all(math.isfinite(v) for v in q):
        raise ValueError(f'quaternion {list(q)} has a non-finite component')
    norm_squared = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
    if not abs(norm_squared - 1.0) < QUATERNION_NORM_TOLERANCE:
        raise ValueError(f'quaternion {list(q)} is not of unit length (squared norm '
                         f'{norm_squared:.6g})')
    scale = 1.0 / math.sqrt(norm_squared)
    return (q[0] * scale, q[1] * scale, q[2] * scale, q[3] * scale)


def quaternion_multiply(a, b):
    """
    Return the Hamilton product ``a * b`` of two ``(x, y, z, w)`` quaternions.

    Parameters
    ----------
    a, b : (4,) ndarray of float64
        ``(x, y, z, w)``.

    Returns
    -------
    (4,) ndarray of float64

    """
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw,
                     aw * bw - ax * bx - ay * by - az * bz])


def _multiply(a, b):
    """Return the Hamilton product of two ``(x, y, z, w)`` float tuples (the hot path)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def _rotate(q, v):
    """Rotate the float vector ``v`` by the unit quaternion ``q`` (``v + 2u x (u x v + w v)``)."""
    x, y, z, w = q
    vx, vy, vz = v
    # t = 2 (u x v)
    tx = 2.0 * (y * vz - z * vy)
    ty = 2.0 * (z * vx - x * vz)
    tz = 2.0 * (x * vy - y * vx)
    return (vx + w * tx + (y * tz - z * ty),
            vy + w * ty + (z * tx - x * tz),
            vz + w * tz + (x * ty - y * tx))


def _normalised(q):
    scale = 1.0 / math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return (q[0] * scale, q[1] * scale, q[2] * scale, q[3] * scale)


def _slerp(a, b, ratio):
    """`slerp` on float tuples."""
    dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
    if dot < 0.0:
        b, dot = (-b[0], -b[1], -b[2], -b[3]), -dot
    if dot > 1.0 - 1e-12:
        return _normalised(tuple(p + ratio * (q - p) for p, q in zip(a, b)))
    theta = math.acos(dot)
    sin_theta = math.sin(theta)
    wa = math.sin((1.0 - ratio) * theta) / sin_theta
    wb = math.sin(ratio * theta) / sin_theta
    return tuple(wa * p + wb * q for p, q in zip(a, b))


def quaternion_from_rpy(roll, pitch, yaw):
    """
    Return the ``(x, y, z, w)`` quaternion of ``Rz(yaw) Ry(pitch) Rx(roll)`` [rad].

    Returns
    -------
    (4,) ndarray of float64

    """
    cr, sr = math.cos(roll / 2.0), math.sin(roll / 2.0)
    cp, sp = math.cos(pitch / 2.0), math.sin(pitch / 2.0)
    cy, sy = math.cos(yaw / 2.0), math.sin(yaw / 2.0)
    return np.array([sr * cp * cy - cr * sp * sy,
                     cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy,
                     cr * cp * cy + sr * sp * sy])


def slerp(a, b, ratio):
    """
    Spherical linear interpolation between two unit quaternions, the shorter way round.

    As tf2's ``Quaternion::slerp`` (used by ``TimeCache::interpolate``): ``ratio`` 0 gives
    ``a``, 1 gives ``b`` (or ``-b``, the same rotation); when ``a`` and ``b`` point into
    opposite half-spaces, ``-b`` is taken so that the rotation turns by at most pi.

    Parameters
    ----------
    a, b : (4,) ndarray of float64
        Unit quaternions.
    ratio : float
        Fraction of the way from ``a`` to ``b``.

    Returns
    -------
    (4,) ndarray of float64
        A unit quaternion.

    """
    # Nearly equal quaternions (dot > 1 - 1e-12): the chord, normalised.
    return np.array(_slerp(tuple(map(float, a)), tuple(map(float, b)), float(ratio)))


class Transform3D:
    """
    A rigid transform ``T_ab``: frame ``b`` placed in frame ``a``.

    Parameters
    ----------
    translation : sequence of 3 float, optional
        Origin of ``b`` in ``a`` [m]; default the origin.
    rotation : sequence of 4 float, optional
        ``(x, y, z, w)`` quaternion turning ``a``'s axes into ``b``'s; default none. Normalised
        (see `unit_quaternion`).

    Attributes
    ----------
    translation : (3,) ndarray of float64, [m]
        Read-only: a transform never changes (buffers share them).
    rotation : (4,) ndarray of float64
        Unit quaternion ``(x, y, z, w)``, read-only.

    Raises
    ------
    ValueError
        When the translation is not 3 finite numbers or the rotation not a unit quaternion.

    Examples
    --------
    >>> import math
    >>> laser_in_base = Transform3D((0.3, 0.0, 0.2), quaternion_from_rpy(math.pi, 0.0, 0.0))
    >>> laser_in_base.apply((1.0, 0.5, 0.0)).round(6).tolist()
    [1.3, -0.5, 0.2]

    """

    __slots__ = ('translation', 'rotation', '_t', '_q')

    def __init__(self, translation=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0, 1.0)):
        t = _floats(translation, 3, 'a translation is 3 finite numbers [m]')
        if not all(math.isfinite(v) for v in t):
            raise ValueError(f'a translation is 3 finite numbers [m], got {translation!r}')
        self._t, self._q = t, _unit_quaternion(rotation)
        self.translation = np.array(self._t)
        self.rotation = np.array(self._q)
        self.translation.flags.writeable = False
        self.rotation.flags.writeable = False

    @classmethod
    def _of(cls, t, q):
        """Return a transform of float tuples already checked (no validation: the hot path)."""
        result = cls.__new__(cls)
        result._t, result._q = t, q
        result.translation = np.array(t)
        result.rotation = np.array(q)
        result.translation.flags.writeable = False
        result.rotation.flags.writeable = False
        return result

    @classmethod
    def identity(cls):
        """Return the identity transform."""
        return cls()

    @classmethod
    def from_xyz_rpy(cls, x=0.0, y=0.0, z=0.0, roll=0.0, pitch=0.0, yaw=0.0):
        """Return the transform of a translation [m] and roll, pitch, yaw [rad]."""
        return cls((x, y, z), quaternion_from_rpy(roll, pitch, yaw))

    def __repr__(self):
        return (f'Transform3D(translation={self.translation.tolist()}, '
                f'rotation={self.rotation.tolist()})')

    def rotation_matrix(self):
        """
        Return the rotation as a matrix.

        Returns
        -------
        (3, 3) ndarray of float64
            ``R`` with ``p_a = R p_b + t``.

        """
        x, y, z, w = self.rotation
        return np.array([
            [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w)],
            [2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w)],
            [2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y)]])

    def compose(self, other):
        """
        Return ``self @ other``: with ``self = T_ab`` and ``other = T_bc``, ``T_ac``.

        Parameters
        ----------
        other : Transform3D
            ``T_bc``.

        Returns
        -------
        Transform3D

        """
        moved = _rotate(self._q, other._t)
        return Transform3D._of(
            (self._t[0] + moved[0], self._t[1] + moved[1], self._t[2] + moved[2]),
            _normalised(_multiply(self._q, other._q)))

    __matmul__ = compose

    def inverse(self):
        """Return ``T_ba`` for ``self = T_ab``."""
        x, y, z, w = self._q
        conjugate = (-x, -y, -z, w)
        back = _rotate(conjugate, self._t)
        return Transform3D._of((-back[0], -back[1], -back[2]), conjugate)

    def apply(self, points):
        """
        Map points from frame ``b`` into frame ``a``.

        Parameters
        ----------
        points : (3,) or (N, 3) or (N, 2) array_like of float, [m]
            Points in ``b``; planar points ``(N, 2)`` are taken at ``z = 0``.

        Returns
        -------
        (3,) or (N, 3) ndarray of float64, [m]
            The points in ``a``.

        Raises
        ------
        ValueError
            For any other shape.

        """
        p = np.asarray(points, dtype=np.float64)
        if p.ndim == 2 and p.shape[1] == 2:
            p = np.column_stack([p, np.zeros(len(p))])
        if p.shape == (3,):
            return self.rotation_matrix() @ p + self.translation
        if p.ndim != 2 or p.shape[1] != 3:
            raise ValueError(f'points have shape (3,), (N, 3) or (N, 2), got {p.shape}')
        return p @ self.rotation_matrix().T + self.translation

    def interpolate(self, other, ratio):
        """
        Interpolate as tf2's ``TimeCache::interpolate``: translation linear, rotation slerp.

        Parameters
        ----------
        other : Transform3D
            The transform at ``ratio`` 1.
        ratio : float
            0 gives ``self``, 1 gives ``other``.

        Returns
        -------
        Transform3D

        """
        ratio = float(ratio)
        return Transform3D._of(tuple(a + ratio * (b - a) for a, b in zip(self._t, other._t)),
                               _slerp(self._q, other._q, ratio))

    @property
    def roll(self):
        """Rotation about x [rad], in ``[-pi, pi]`` (tf2's ``getRPY``)."""
        x, y, z, w = self.rotation
        return math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))

    @property
    def pitch(self):
        """Rotation about y [rad], in ``[-pi/2, pi/2]`` (tf2's ``getRPY``)."""
        x, y, z, w = self.rotation
        return math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))

    @property
    def yaw(self):
        """Rotation about z [rad], in ``[-pi, pi]``: the heading of the x axis (``getRPY``)."""
        x, y, z, w = self.rotation
        return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))

    def is_close(self, other, atol=1e-9):
        """
        Return whether two transforms agree within ``atol``.

        Translations are compared component by component [m], rotations as rotations
        (``q`` and ``-q`` are the same).

        """
        same_rotation = min(np.max(np.abs(self.rotation - other.rotation)),
                            np.max(np.abs(self.rotation + other.rotation))) <= atol
        return bool(np.all(np.abs(self.translation - other.translation) <= atol)
                    and same_rotation)
