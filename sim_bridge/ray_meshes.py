"""
Triangle-mesh twins of collision shapes, for the laser's rays only.

Bullet casts a ray against a box or a convex hull with an iterative GJK convex cast, and
pybullet applies a ray's ``collisionFilterMask`` only after that narrow-phase test: every
body whose bounding box a beam crosses costs a cast, even behind a wall or outside the mask.
A beam crosses most of the map (``range_max`` 30 m). On back_and_forth a 640-beam scan spent
about 1.3 ms in casts against the twelve wall boxes, and about 3 us more for every beam that
crossed the bounding box of a P3-AT (a box and four 32-sided wheel hulls): up to 5 ms more
per scan with ten wanderers, most of the simulator's time. A concave triangle mesh answers a
ray with exact ray-triangle tests through its own bounding volume hierarchy: about 0.4 ms for
the walls and 0.4 us per beam and P3-AT. So the scene gives the rays mesh twins of the walls
and the wanderers and keeps the primitive shapes for the Husky's contacts (see
`sim_bridge.scene`).

The twins reproduce the collision geometry: boxes exactly, and a URDF cylinder as pybullet's
URDF importer builds it, a convex hull of ``CYLINDER_SIDES`` sides with a vertex on the local
+y axis, padded by the hull's collision margin (its faces moved out by ``HULL_MARGIN``; Bullet
rounds the edges instead, which differs by less than half the margin). The convex cast stops
up to about a millimetre short of a surface, so ranges on the twins differ from those on the
primitive shapes by that much (under 2 mm for 99 % of the beams that hit a wanderer); a beam
that grazes the edge of a wheel may hit it on one and pass it on the other.

Vertices are ``(V, 3) ndarray of float64`` [m] and triangles ``(T, 3) ndarray of int64``
(vertex indices, counter-clockwise seen from outside).

"""

import math
import xml.etree.ElementTree as ElementTree

import numpy as np

#: Sides of the prism pybullet's URDF importer makes of a cylinder.
CYLINDER_SIDES = 32
#: Collision margin of the hulls pybullet's URDF importer makes [m].
HULL_MARGIN = 0.001
#: Corners of a unit box, and its 12 triangles (two per face).
_BOX_CORNERS = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)],
                        dtype=np.float64)
_BOX_TRIANGLES = np.array([(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                           (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)],
                          dtype=np.int64)


def box_mesh(centres, half_extents):
    """
    Mesh axis-aligned boxes.

    Parameters
    ----------
    centres, half_extents : (K, 3) array_like of float
        Centre and half size of each box [m]; half sizes positive.

    Returns
    -------
    vertices : (8 K, 3) ndarray of float64
    triangles : (12 K, 3) ndarray of int64

    """
    centres = np.asarray(centres, dtype=np.float64).reshape(-1, 3)
    half_extents = np.asarray(half_extents, dtype=np.float64).reshape(-1, 3)
    if centres.shape != half_extents.shape:
        raise ValueError(f'centres {centres.shape} and half_extents {half_extents.shape} must '
                         'have the same shape')
    if not np.all(half_extents > 0.0):
        raise ValueError('box half extents must be positive')
    vertices = centres[:, np.newaxis] + half_extents[:, np.newaxis] * _BOX_CORNERS
    triangles = _BOX_TRIANGLES + 8 * np.arange(len(centres))[:, np.newaxis, np.newaxis]
    return vertices.reshape(-1, 3), triangles.reshape(-1, 3)


def cylinder_mesh(radius, length, sides=CYLINDER_SIDES, margin=HULL_MARGIN):
    """
    Mesh a cylinder along its local z axis as pybullet's URDF importer shapes it.

    Parameters
    ----------
    radius, length : float
        Radius and length of the cylinder [m], positive.
    sides : int
        Sides of the prism, at least 3; its first vertex lies on the local +y axis.
    margin : float
        Collision margin the faces are moved out by [m], non-negative.

    Returns
    -------
    vertices : (2 sides, 3) ndarray of float64
    triangles : (4 sides - 4, 3) ndarray of int64

    """
    if not (radius > 0.0 and length > 0.0 and margin >= 0.0) or sides < 3:
        raise ValueError(f'need radius > 0, length > 0, margin >= 0 and sides >= 3, got '
                         f'{radius!r}, {length!r}, {margin!r} and {sides!r}')
    theta = 2.0 * math.pi * np.arange(sides) / sides
    corner = radius + margin / math.cos(math.pi / sides)  # faces moved out by the margin
    half = 0.5 * length + margin
    ring = np.column_stack([corner * np.sin(theta), corner * np.cos(theta)])
    vertices = np.concatenate([np.column_stack([ring, np.full(sides, half)]),
                               np.column_stack([ring, np.full(sides, -half)])])
    k = np.arange(sides)
    nxt = (k + 1) % sides
    sides_tri = np.concatenate([np.column_stack([k, nxt, k + sides]),
                                np.column_stack([nxt, nxt + sides, k + sides])])
    # Caps as a zigzag strip across the polygon (vertices 0, 1, n - 1, 2, n - 2, ...), not a
    # fan: thin bands, so that a ray meets the bounding boxes of few of their triangles.
    zigzag = [0]
    for step in range(1, sides // 2 + 1):
        zigzag += [step] if step == sides - step else [step, sides - step]
    strip = np.array([zigzag[j:j + 3] if j % 2 else zigzag[j:j + 3][::-1]
                      for j in range(sides - 2)])
    caps = np.concatenate([strip, strip[:, ::-1] + sides])
    return vertices, np.concatenate([sides_tri, caps])


def rpy_matrix(roll, pitch, yaw):
    """
    Return the rotation matrix of URDF ``rpy`` angles.

    Parameters
    ----------
    roll, pitch, yaw : float
        Rotations about the fixed x, then y, then z axis [rad].

    Returns
    -------
    (3, 3) ndarray of float64

    """
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def urdf_collision_mesh(path):
    """
    Mesh the collision boxes and cylinders of a one-link URDF in its base frame.

    Parameters
    ----------
    path : str or pathlib.Path
        The URDF file.

    Returns
    -------
    vertices : (V, 3) ndarray of float64
    triangles : (T, 3) ndarray of int64

    Raises
    ------
    ValueError
        If the URDF has more than one link, no collision element, or a collision geometry
        other than a box or a cylinder.

    """
    robot = ElementTree.parse(str(path)).getroot()
    links = robot.findall('link')
    if len(links) != 1:
        raise ValueError(f'{path}: expected one link, found {len(links)}')
    parts = []
    for collision in links[0].findall('collision'):
        origin = collision.find('origin')
        xyz = _floats(origin, 'xyz') if origin is not None else [0.0, 0.0, 0.0]
        rpy = _floats(origin, 'rpy') if origin is not None else [0.0, 0.0, 0.0]
        box = collision.find('geometry/box')
        cylinder = collision.find('geometry/cylinder')
        if box is not None:
            vertices, triangles = box_mesh([0.0, 0.0, 0.0], 0.5 * np.array(_floats(box, 'size')))
        elif cylinder is not None:
            vertices, triangles = cylinder_mesh(float(cylinder.get('radius')),
                                                float(cylinder.get('length')))
        else:
            raise ValueError(f'{path}: only box and cylinder collision geometry can be meshed')
        parts.append((vertices @ rpy_matrix(*rpy).T + xyz, triangles))
    if not parts:
        raise ValueError(f'{path}: no collision geometry')
    return merge_meshes(parts)


def merge_meshes(parts):
    """
    Join meshes into one.

    Parameters
    ----------
    parts : sequence of (vertices, triangles)
        The meshes, each as this module returns them.

    Returns
    -------
    vertices : (V, 3) ndarray of float64
    triangles : (T, 3) ndarray of int64

    """
    offsets = np.cumsum([0] + [len(vertices) for vertices, _ in parts[:-1]])
    vertices = np.concatenate([vertices for vertices, _ in parts])
    triangles = np.concatenate([triangles + offset for (_, triangles), offset
                                in zip(parts, offsets)])
    return vertices, triangles


def _floats(element, name):
    # URDF: a missing xyz or rpy of an <origin> means zeros.
    return [float(v) for v in element.get(name, '0 0 0').split()]
