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
    q = np.asarray(rotation, dtype=np.float64)
    if q.shape != (4,):
        raise ValueError(f'a quaternion has 4 components (x, y, z, w), got shape {q.shape}')
    if not np.all(np.isfinite(q)):
        raise ValueError(f'quaternion {q.tolist()} has a non-finite component')
    norm_squared = float(q @ q)
    if not abs(norm_squared - 1.0) < QUATERNION_NORM_TOLERANCE:
        raise ValueError(f'quaternion {q.tolist()} is not of unit length (squared norm '
                         f'{norm_squared:.6g})')
    return q / math.sqrt(norm_squared)


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
    dot = float(a @ b)
    if dot < 0.0:
        b, dot = -b, -dot
    if dot > 1.0 - 1e-12:
        q = a + ratio * (b - a)      # nearly equal: the chord, normalised
        return q / math.sqrt(float(q @ q))
    theta = math.acos(dot)
    sin_theta = math.sin(theta)
    return (math.sin((1.0 - ratio) * theta) * a + math.sin(ratio * theta) * b) / sin_theta


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
    rotation : (4,) ndarray of float64
        Unit quaternion ``(x, y, z, w)``.

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

    __slots__ = ('translation', 'rotation')

    def __init__(self, translation=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0, 1.0)):
        t = np.array(translation, dtype=np.float64)
        if t.shape != (3,) or not np.all(np.isfinite(t)):
            raise ValueError(f'a translation is 3 finite numbers [m], got {translation!r}')
        self.translation = t
        self.rotation = unit_quaternion(rotation)

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
        result = Transform3D.__new__(Transform3D)
        result.translation = self.translation + self.rotation_matrix() @ other.translation
        q = quaternion_multiply(self.rotation, other.rotation)
        result.rotation = q / math.sqrt(float(q @ q))
        return result

    __matmul__ = compose

    def inverse(self):
        """Return ``T_ba`` for ``self = T_ab``."""
        result = Transform3D.__new__(Transform3D)
        x, y, z, w = self.rotation
        result.rotation = np.array([-x, -y, -z, w])
        result.translation = -(self.rotation_matrix().T @ self.translation)
        return result

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
        result = Transform3D.__new__(Transform3D)
        result.translation = self.translation + ratio * (other.translation - self.translation)
        result.rotation = slerp(self.rotation, other.rotation, ratio)
        return result

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
