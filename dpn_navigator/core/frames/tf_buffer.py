"""
A TF buffer with tf2's rules, in plain Python: transforms of a frame tree stored over time.

Fed with transforms (parent, child, stamp, translation, rotation, static), as from ``/tf`` and
``/tf_static``, it answers "where is frame ``source`` in frame ``target`` at time ``t``" the way
tf2's ``BufferCore`` (geometry2, ``tf2/src/buffer_core.cpp`` and ``cache.cpp``) does:

- **static** transforms (``/tf_static``, tf2's ``StaticCache``) hold at all times; a new one
  for the same child replaces the old;
- **dynamic** transforms (tf2's ``TimeCache``) are kept sorted by stamp; a query between two
  samples interpolates them (translation linearly, rotation by slerp, ``TimeCache::
  interpolate``); a query at a sample's stamp returns it; a query before the oldest or after
  the newest sample, or on a frame with a single sample at another time, is an
  `ExtrapolationError` (``BufferCore`` never extrapolates);
- time **0** means the latest common time of the links between the two frames
  (``getLatestCommonTime``: the earliest of their newest stamps, static links not counting;
  0 when all are static);
- a lookup goes from the source frame up to the common ancestor and down to the target frame;
  unknown frames are a `FrameLookupError`, frames of two separate trees a `ConnectivityError`;
- the cache keeps ``cache_duration_ns`` (tf2's default 10 s) behind each frame's newest
  sample: older samples are pruned and a sample older than that is refused (tf2's
  ``TF_OLD_DATA``); ``cache_duration_ns=None`` keeps everything (offline use, e.g. a bag
  read whole before the first lookup);
- a transform with an empty frame name, equal parent and child, a NaN, or a quaternion whose
  squared norm is off 1 by 0.01 or more is an `InvalidTransformError` (tf2 logs and ignores
  these); leading slashes are stripped from the names given to `TfBuffer.set_transform`
  (tf2's ``stripSlash``), and refused in lookups (tf2's ``validateFrameId``).

Two choices are stricter than tf2, to keep one tree with clear errors: a child frame keeps
the parent it was first given (tf2 lets a frame change parent over time; here a second parent
is an `InvalidTransformError`), and a transform that would close a loop is refused when it is
set (tf2 reports the loop at lookup). A second transform at the same stamp for the same child
replaces the first (tf2 keeps both and returns the newer one at that stamp).

"""

import bisect
import math

import numpy as np

from .transform3d import Transform3D

#: tf2's ``BUFFER_CORE_DEFAULT_CACHE_TIME`` [ns].
DEFAULT_CACHE_DURATION_NS = 10_000_000_000


class TransformError(Exception):
    """A transform cannot be set or looked up (tf2's ``TransformException``)."""


class InvalidTransformError(TransformError, ValueError):
    """A transform given to the buffer is malformed or does not fit the tree."""


class FrameLookupError(TransformError, LookupError):
    """A frame name is unknown or malformed (tf2's ``LookupException``/``InvalidArgument``)."""


class ConnectivityError(TransformError):
    """Two frames are not in one tree (tf2's ``ConnectivityException``)."""


class ExtrapolationError(TransformError):
    """
    A lookup needs a time outside the stored samples (tf2's ``ExtrapolationException``).

    Attributes
    ----------
    frame : str
        The child frame whose link has no data at ``stamp_ns``.
    stamp_ns : int
        The requested time [ns].
    earliest_ns, latest_ns : int or None
        The link's stored interval [ns] (None when it holds nothing).

    """

    def __init__(self, message, frame, stamp_ns, earliest_ns, latest_ns):
        super().__init__(message)
        self.frame = frame
        self.stamp_ns = stamp_ns
        self.earliest_ns = earliest_ns
        self.latest_ns = latest_ns


class _Link:
    """The transforms of one child frame in its parent: one static value, or a history."""

    __slots__ = ('parent', 'static', 'stamps', 'values')

    def __init__(self, parent, static):
        self.parent = parent
        self.static = static
        self.stamps = []        # sorted [ns]; a static link keeps its one stamp here
        self.values = []        # Transform3D per stamp

    def latest(self):
        """Return the newest stamp [ns] (0 for a static link, as tf2's ``StaticCache``)."""
        return 0 if self.static else self.stamps[-1]

    def insert(self, stamp_ns, value, cache_duration_ns):
        """Store a sample; return False when it is older than the cache keeps."""
        if self.static:
            self.stamps, self.values = [stamp_ns], [value]
            return True
        if cache_duration_ns is not None and self.stamps:
            latest = self.stamps[-1]
            if stamp_ns < latest - cache_duration_ns:
                return False
        index = bisect.bisect_left(self.stamps, stamp_ns)
        if index < len(self.stamps) and self.stamps[index] == stamp_ns:
            self.values[index] = value
        else:
            self.stamps.insert(index, stamp_ns)
            self.values.insert(index, value)
        if cache_duration_ns is not None:
            # tf2's pruneList: drop what lies more than the duration behind the newest.
            oldest_kept = bisect.bisect_left(self.stamps, self.stamps[-1] - cache_duration_ns)
            if oldest_kept:
                del self.stamps[:oldest_kept]
                del self.values[:oldest_kept]
        return True

    def at(self, child, stamp_ns):
        """Return the transform at ``stamp_ns`` (tf2's ``findClosest`` and ``interpolate``)."""
        if self.static:
            return self.values[0]
        stamps = self.stamps
        earliest, latest = stamps[0], stamps[-1]
        if stamp_ns > latest:
            raise ExtrapolationError(
                f'lookup would require extrapolation into the future: requested time '
                f'{_seconds(stamp_ns)} but the latest data of frame {child!r} (in {self.parent!r})'
                f' is at time {_seconds(latest)}', child, stamp_ns, earliest, latest)
        if stamp_ns < earliest:
            raise ExtrapolationError(
                f'lookup would require extrapolation into the past: requested time '
                f'{_seconds(stamp_ns)} but the earliest data of frame {child!r} (in '
                f'{self.parent!r}) is at time {_seconds(earliest)}', child, stamp_ns, earliest,
                latest)
        index = bisect.bisect_left(stamps, stamp_ns)
        if stamps[index] == stamp_ns:
            return self.values[index]
        older, newer = index - 1, index
        ratio = (stamp_ns - stamps[older]) / (stamps[newer] - stamps[older])
        return self.values[older].interpolate(self.values[newer], ratio)


def _seconds(stamp_ns):
    return f'{stamp_ns / 1e9:.9f}'


def _frame_name(name, what):
    """Return a frame name with leading slashes stripped; refuse an empty one."""
    if not isinstance(name, str):
        raise InvalidTransformError(f'{what} must be a string, got {name!r}')
    stripped = name.lstrip('/')
    if not stripped:
        raise InvalidTransformError(f'{what} is empty: in tf2 frame names cannot be empty')
    return stripped


class TfBuffer:
    """
    Transforms of a frame tree over time, looked up with tf2's rules (see the module).

    Parameters
    ----------
    cache_duration_ns : int or None, optional
        How far behind a frame's newest sample its samples are kept [ns]; tf2's default
        10 s (`DEFAULT_CACHE_DURATION_NS`). None keeps every sample (offline use).

    Examples
    --------
    >>> buffer = TfBuffer()
    >>> buffer.set_transform('map', 'odom', 0, (1.0, 0.0, 0.0), (0, 0, 0, 1), static=True)
    True
    >>> buffer.set_transform('odom', 'base_link', 10, (0.0, 0.0, 0.0), (0, 0, 0, 1))
    True
    >>> buffer.set_transform('odom', 'base_link', 20, (2.0, 0.0, 0.0), (0, 0, 0, 1))
    True
    >>> buffer.set_transform('base_link', 'laser', 0, (0.5, 0, 0), (0, 0, 0, 1), static=True)
    True
    >>> buffer.lookup('map', 'laser', 15).translation.tolist()
    [2.5, 0.0, 0.0]

    """

    def __init__(self, cache_duration_ns=DEFAULT_CACHE_DURATION_NS):
        if cache_duration_ns is not None and not int(cache_duration_ns) >= 0:
            raise ValueError(f'cache_duration_ns must be >= 0 or None, got {cache_duration_ns}')
        self.cache_duration_ns = None if cache_duration_ns is None else int(cache_duration_ns)
        self._links = {}        # child frame -> _Link
        self._frames = set()    # every frame named as a parent or a child

    def set_transform(self, parent_frame, child_frame, stamp_ns, translation, rotation,
                      static=False):
        """
        Store the pose of ``child_frame`` in ``parent_frame`` at ``stamp_ns``.

        Parameters
        ----------
        parent_frame, child_frame : str
            ``header.frame_id`` and ``child_frame_id`` of a ``TransformStamped``; leading
            slashes are stripped.
        stamp_ns : int
            ``header.stamp`` [ns]; ignored for the lookups of a static transform.
        translation : sequence of 3 float, [m]
            Origin of the child frame in the parent frame.
        rotation : sequence of 4 float
            ``(x, y, z, w)``; normalised when within tf2's tolerance of unit length.
        static : bool, optional
            True for ``/tf_static``: valid at all times, replacing the frame's history.

        Returns
        -------
        bool
            True when stored; False when the cache is bounded and the sample lies farther
            behind the frame's newest one than it keeps (tf2's ``TF_OLD_DATA``).

        Raises
        ------
        InvalidTransformError
            For an empty frame name, equal parent and child, a non-finite value, a rotation
            that is not a unit quaternion, a child already given another parent, or a
            transform that would close a loop.

        """
        parent = _frame_name(parent_frame, 'parent frame')
        child = _frame_name(child_frame, 'child frame')
        if parent == child:
            raise InvalidTransformError(
                f'transform from {parent!r} to itself: frame and child frame must differ')
        try:
            value = Transform3D(translation, rotation)
        except ValueError as error:
            raise InvalidTransformError(f'transform {parent!r} -> {child!r}: {error}') from None
        stamp = int(stamp_ns)
        link = self._links.get(child)
        if link is not None and link.parent != parent:
            raise InvalidTransformError(
                f'frame {child!r} already has the parent {link.parent!r}; a transform giving it '
                f'the parent {parent!r} is refused (one tree, one parent per frame)')
        if link is None:
            ancestor = parent
            while ancestor in self._links:
                ancestor = self._links[ancestor].parent
                if ancestor == child:
                    raise InvalidTransformError(
                        f'transform {parent!r} -> {child!r} would close a loop: {parent!r} '
                        f'already lies below {child!r}')
        if link is None or link.static != bool(static):
            link = _Link(parent, bool(static))      # tf2's allocateFrame on a kind change
            self._links[child] = link
        self._frames.update((parent, child))
        return link.insert(stamp, value, self.cache_duration_ns)

    @property
    def frames(self):
        """Return every frame name the buffer knows (parents and children), a frozenset."""
        return frozenset(self._frames)

    def parent(self, frame):
        """Return the parent of ``frame``, or None for a root; `FrameLookupError` if unknown."""
        self._check_frame(frame, 'frame')
        link = self._links.get(frame)
        return None if link is None else link.parent

    def is_static(self, frame):
        """Return whether ``frame``'s link to its parent is static (False for a root)."""
        self._check_frame(frame, 'frame')
        return frame in self._links and self._links[frame].static

    def time_range(self, frame):
        """
        Return the stamps ``(earliest, latest)`` [ns] of ``frame``'s dynamic link.

        None for a static link or a root (valid at all times).

        """
        self._check_frame(frame, 'frame')
        link = self._links.get(frame)
        if link is None or link.static:
            return None
        return link.stamps[0], link.stamps[-1]

    def sample_step(self, frame, stamp_ns):
        """
        Return how far apart the two samples of ``frame``'s link around ``stamp_ns`` lie.

        A lookup at ``stamp_ns`` interpolates between them; across a long step in which the
        frame accelerates (a robot starting a turn), the interpolated pose is off.

        Returns
        -------
        (float, float, float) or None
            ``(duration [s], distance [m], turn [rad])`` between the two samples; zeros when a
            sample lies at ``stamp_ns``; None for a static link, a root, or a stamp outside the
            kept samples.

        """
        self._check_frame(frame, 'frame')
        link = self._links.get(frame)
        if link is None or link.static:
            return None
        stamps = link.stamps
        stamp = int(stamp_ns)
        if not stamps[0] <= stamp <= stamps[-1]:
            return None
        index = bisect.bisect_left(stamps, stamp)
        if stamps[index] == stamp:
            return 0.0, 0.0, 0.0
        older, newer = link.values[index - 1], link.values[index]
        step = older.inverse() @ newer
        w = min(1.0, abs(float(step.rotation[3])))
        return ((stamps[index] - stamps[index - 1]) * 1e-9,
                float(np.linalg.norm(step.translation)), 2.0 * math.acos(w))

    def clear(self):
        """Forget every transform and frame."""
        self._links.clear()
        self._frames.clear()

    def _check_frame(self, frame, what):
        if not isinstance(frame, str) or not frame:
            raise FrameLookupError(f'invalid {what} {frame!r}: in tf2 frame names cannot be '
                                   'empty')
        if frame.startswith('/'):
            raise FrameLookupError(f'invalid {what} {frame!r}: in tf2 frame names cannot start '
                                   "with a '/'")
        if frame not in self._frames:
            raise FrameLookupError(f'{what} {frame!r} does not exist (known: '
                                   f'{", ".join(sorted(self._frames)) or "none"})')

    def _path_to_root(self, frame):
        """Return ``[frame, parent, grandparent, ..., root]``."""
        path = [frame]
        while path[-1] in self._links:
            path.append(self._links[path[-1]].parent)
        return path

    def _chains(self, target_frame, source_frame):
        """Return the frames from source and target up to, without, their common ancestor."""
        self._check_frame(target_frame, 'target frame')
        self._check_frame(source_frame, 'source frame')
        source_path = self._path_to_root(source_frame)
        target_path = self._path_to_root(target_frame)
        if source_path[-1] != target_path[-1]:
            raise ConnectivityError(
                f'could not find a connection between {target_frame!r} and {source_frame!r}: '
                f'they are in two unconnected trees (roots {target_path[-1]!r} and '
                f'{source_path[-1]!r})')
        on_target_path = set(target_path)
        common = next(frame for frame in source_path if frame in on_target_path)
        return (source_path[:source_path.index(common)],
                target_path[:target_path.index(common)])

    def latest_common_time(self, target_frame, source_frame):
        """
        Return the latest time both frames can be looked up at [ns] (tf2's rule).

        The earliest of the newest stamps of the dynamic links between the two frames; 0 when
        all are static; for equal frames, that frame's newest stamp (0 if static or a root).

        Raises
        ------
        FrameLookupError, ConnectivityError

        """
        if target_frame == source_frame:
            self._check_frame(source_frame, 'source frame')
            link = self._links.get(source_frame)
            return 0 if link is None else link.latest()
        source_chain, target_chain = self._chains(target_frame, source_frame)
        stamps = [self._links[frame].latest() for frame in source_chain + target_chain
                  if not self._links[frame].static]
        return min(stamps) if stamps else 0

    def lookup(self, target_frame, source_frame, stamp_ns=0, zero_is_latest=True):
        """
        Return the pose of ``source_frame`` in ``target_frame`` at ``stamp_ns``.

        As tf2's ``lookupTransform(target_frame, source_frame, time)``: the returned
        ``T_target_source`` maps points given in ``source_frame`` into ``target_frame``.

        Parameters
        ----------
        target_frame, source_frame : str
            The frame to express the pose in, and the frame whose pose is asked.
        stamp_ns : int, optional
            [ns]; 0 (the default) for the latest common time.
        zero_is_latest : bool, optional
            False: a stamp of 0 is the time 0 (a simulation's first instant), not the latest
            common time.

        Returns
        -------
        Transform3D

        Raises
        ------
        FrameLookupError
            A frame is unknown, empty or starts with ``/``.
        ConnectivityError
            The frames are in two trees.
        ExtrapolationError
            A dynamic link between them has no data around ``stamp_ns``.

        """
        stamp = int(stamp_ns)
        if target_frame == source_frame:
            self._check_frame(source_frame, 'source frame')
            return Transform3D.identity()
        source_chain, target_chain = self._chains(target_frame, source_frame)
        if stamp == 0 and zero_is_latest:
            stamp = self.latest_common_time(target_frame, source_frame)
        ancestor_from_source = self._chain(source_chain, stamp)
        ancestor_from_target = self._chain(target_chain, stamp)
        if ancestor_from_target is None:            # the target is the common ancestor
            return ancestor_from_source
        if ancestor_from_source is None:            # the source is the common ancestor
            return ancestor_from_target.inverse()
        return ancestor_from_target.inverse() @ ancestor_from_source

    def _chain(self, chain, stamp):
        """Return the pose of ``chain[0]`` in the parent of ``chain[-1]`` (None if empty)."""
        result = None
        for frame in reversed(chain):
            link = self._links[frame].at(frame, stamp)
            result = link if result is None else result @ link
        return result

    def can_transform(self, target_frame, source_frame, stamp_ns=0, zero_is_latest=True):
        """
        Return whether `lookup` would succeed with these arguments (never raises).

        Returns
        -------
        bool

        """
        try:
            self.lookup(target_frame, source_frame, stamp_ns, zero_is_latest)
        except TransformError:
            return False
        return True
