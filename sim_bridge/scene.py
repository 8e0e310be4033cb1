"""
The pybullet side of the world: one client holding the walls, the Husky and the wanderers.

The robots are kinematic (see `sim_bridge.world`): `Scene` only writes their poses into the
physics engine and asks it for contacts; it never steps the dynamics. Collision filter groups
decide which pairs are checked at all: the Husky against walls and wanderers, and rays against
walls and wanderers; walls, and wanderers among themselves, are never paired.

**Two shapes per obstacle.** The Husky meets the walls' boxes and the wanderers' URDF shapes;
the laser's rays meet triangle-mesh twins of the same geometry (`sim_bridge.ray_meshes`): one
static mesh body for all walls and one per wanderer, moved with it. Each body's mask names
only the side it serves, so Bullet drops the other pairs before any narrow-phase test (the
rays' own ``collisionFilterMask`` is applied by pybullet only after it), and a scan costs a
fast analytic ray-triangle test per body a beam crosses instead of an iterative convex cast.

"""

from contextlib import contextmanager
import math
import os
from pathlib import Path
import sys

import pybullet
import pybullet_data

from .ray_meshes import box_mesh, urdf_collision_mesh
from .robot_profiles import ROBOT_PROFILES
from .walls import build_walls, merge_cells, wall_boxes
from .wanderers import P3AT_URDF

#: Collision filter groups. pybullet's ray tests carry group 1, so bodies the laser must see
#: have bit 1 in their mask; no other body has, so the rays skip them (the Husky included)
#: before any narrow-phase test. pybullet pairs two bodies when either one's group is in the
#: other's mask, so the ray twins have groups of their own, in no mask but the rays'.
RAY_GROUP = 1
WALL_GROUP = 2
HUSKY_GROUP = 4
WANDERER_GROUP = 8
WALL_RAY_GROUP = 16
WANDERER_RAY_GROUP = 32
#: Collision filter mask for the laser's rays.
RAY_MASK = WALL_RAY_GROUP | WANDERER_RAY_GROUP
#: Most boxes in one wall mesh (pybullet takes at most 131072 vertices per shape).
MAX_MESH_BOXES = 8192


class Scene:
    """
    One pybullet client with a scenario's walls, the Husky and ``n_wanderers`` P3-ATs.

    Parameters
    ----------
    scenario : Scenario
        Its occupied cells become static boxes.
    agent_urdf : str or pathlib.Path, or sequence of them
        The wanderers' model (the P3-AT by default; ``agent_urdf`` for another agent), or
        one per wanderer.
    n_wanderers : int
        Number of P3-AT bodies.
    wall_height : float
        Height of the walls [m].
    time_step : float
        The fixed time step [s], set on the engine for completeness.
    gui : bool
        Connect to the pybullet GUI instead of ``DIRECT``.
    body : robot_profiles.RobotBody or None
        The robot's body; None: the Husky's.

    Attributes
    ----------
    client : int or None
        The physics client id; None once closed.
    husky : int
        The robot's body id (the Husky's URDF, or the box of a profile without one).
    wall_bodies, wanderer_bodies : list of int
        Body ids of the walls' boxes and the wanderers' URDF models (what the Husky meets).
    wall_ray_bodies, wanderer_ray_bodies : list of int
        Body ids of their mesh twins (what the rays meet); one per wanderer.

    """

    def __init__(self, scenario, n_wanderers, wall_height, time_step, gui=False,
                 agent_urdf=P3AT_URDF, body=None):
        self._agent_urdf = agent_urdf
        self._body = ROBOT_PROFILES['husky'].body if body is None else body
        self.client = pybullet.connect(pybullet.GUI if gui else pybullet.DIRECT)
        if self.client < 0:
            raise RuntimeError('cannot connect to pybullet' + (' (GUI)' if gui else ''))
        built = False
        try:
            self._build(scenario, n_wanderers, wall_height, time_step, gui)
            built = True
        finally:
            if not built:
                self.close()

    def _build(self, scenario, n_wanderers, wall_height, time_step, gui):
        client = self.client
        pybullet.setRealTimeSimulation(0, physicsClientId=client)
        pybullet.setTimeStep(time_step, physicsClientId=client)
        pybullet.setGravity(0.0, 0.0, -9.81, physicsClientId=client)
        if gui:
            pybullet.configureDebugVisualizer(pybullet.COV_ENABLE_RENDERING, 0,
                                              physicsClientId=client)
            plane = pybullet.loadURDF(os.path.join(pybullet_data.getDataPath(), 'plane.urdf'),
                                      physicsClientId=client)
            pybullet.setCollisionFilterGroupMask(plane, -1, 0, 0, physicsClientId=client)
        rects = merge_cells(scenario.occupied)
        self.wall_bodies = build_walls(client, rects, scenario.geometry, wall_height,
                                       WALL_GROUP, HUSKY_GROUP, visual=gui)
        centres, half_extents = wall_boxes(rects, scenario.geometry, wall_height)
        self.wall_ray_bodies = [
            self._ray_body(self._mesh_shape(*box_mesh(centres[k:k + MAX_MESH_BOXES],
                                                      half_extents[k:k + MAX_MESH_BOXES])),
                           WALL_RAY_GROUP, gui)
            for k in range(0, len(centres), MAX_MESH_BOXES)]
        with _quiet_native_output():
            self.husky = self._robot_body(self._body)
            urdfs = self._agent_urdfs(n_wanderers)
            self.wanderer_bodies = [pybullet.loadURDF(str(urdf), physicsClientId=client)
                                    for urdf in urdfs]
        for link in range(-1, pybullet.getNumJoints(self.husky, physicsClientId=client)):
            pybullet.setCollisionFilterGroupMask(self.husky, link, HUSKY_GROUP,
                                                 WALL_GROUP | WANDERER_GROUP,
                                                 physicsClientId=client)
        for body in self.wanderer_bodies:
            pybullet.setCollisionFilterGroupMask(body, -1, WANDERER_GROUP, HUSKY_GROUP,
                                                 physicsClientId=client)
        shapes = {urdf: self._mesh_shape(*urdf_collision_mesh(urdf)) for urdf in set(urdfs)}
        self.wanderer_ray_bodies = [self._ray_body(shapes[urdf], WANDERER_RAY_GROUP, gui)
                                    for urdf in urdfs]
        self._walls = frozenset(self.wall_bodies)
        self._wanderer_index = {body: i for i, body in enumerate(self.wanderer_bodies)}
        # pybullet places a body by its base's centre of mass; keep each one's offset.
        self._offsets = {}
        for body in [self.husky] + self.wanderer_bodies + self.wanderer_ray_bodies:
            info = pybullet.getDynamicsInfo(body, -1, physicsClientId=client)
            self._offsets[body] = (info[3], info[4])
        if gui:
            pybullet.configureDebugVisualizer(pybullet.COV_ENABLE_RENDERING, 1,
                                              physicsClientId=client)
            x0, y0 = scenario.origin
            pybullet.resetDebugVisualizerCamera(
                0.8 * max(scenario.width, scenario.height), 0.0, -89.0,
                [x0 + 0.5 * scenario.width, y0 + 0.5 * scenario.height, 0.0],
                physicsClientId=client)

    def place(self, body, pose):
        """
        Put a body's base frame at a planar pose on the ground.

        Parameters
        ----------
        body : int
            The body; for a wanderer use `place_wanderer` (and `place_wanderer_ray_twin`).
        pose : (float, float, float)
            ``(x, y, yaw)`` of the URDF base frame in the map frame [m, m, rad].

        """
        x, y, yaw = pose
        self._place(body, x, y, math.cos(yaw), math.sin(yaw), math.cos(0.5 * yaw),
                    math.sin(0.5 * yaw))

    def place_wanderer(self, i, x, y, yaw, ray_twin=True):
        """
        Put wanderer ``i`` (and by default its ray twin) at a planar pose (see `place`).

        Parameters
        ----------
        i : int
            Index of the wanderer.
        x, y, yaw : float
            Pose of its base frame in the map frame [m, m, rad].
        ray_twin : bool
            Also move its ray twin. Only rays meet the twin, so a caller that moves wanderers
            on every tick but casts rays less often may leave it out and move the twin with
            `place_wanderer_ray_twin` before the next ray cast.

        """
        frame = (x, y, math.cos(yaw), math.sin(yaw), math.cos(0.5 * yaw), math.sin(0.5 * yaw))
        self._place(self.wanderer_bodies[i], *frame)
        if ray_twin:
            self._place(self.wanderer_ray_bodies[i], *frame)

    def place_wanderer_ray_twin(self, i, x, y, yaw):
        """Put the ray twin of wanderer ``i`` at a planar pose (see `place_wanderer`)."""
        self._place(self.wanderer_ray_bodies[i], x, y, math.cos(yaw), math.sin(yaw),
                    math.cos(0.5 * yaw), math.sin(0.5 * yaw))

    def _place(self, body, x, y, cos_yaw, sin_yaw, cos_half, sin_half):
        # The base frame turned by yaw about z, composed with the centre-of-mass offset
        # (pybullet places a body by its centre of mass).
        (ox, oy, oz), (qx, qy, qz, qw) = self._offsets[body]
        pybullet.resetBasePositionAndOrientation(
            body, (x + cos_yaw * ox - sin_yaw * oy, y + sin_yaw * ox + cos_yaw * oy, oz),
            (cos_half * qx - sin_half * qy, cos_half * qy + sin_half * qx,
             cos_half * qz + sin_half * qw, cos_half * qw - sin_half * qz),
            physicsClientId=self.client)

    def husky_contacts(self):
        """
        Run collision detection and report what the Husky penetrates.

        Returns
        -------
        wall : bool
            Whether it penetrates any wall.
        wanderers : set of int
            Indices of the wanderers it penetrates.
        depth : float
            The deepest penetration [m], 0 without contact.

        """
        pybullet.performCollisionDetection(physicsClientId=self.client)
        wall = False
        wanderers = set()
        depth = 0.0
        for point in pybullet.getContactPoints(bodyA=self.husky, physicsClientId=self.client):
            distance = point[8]
            if distance >= 0.0:  # within the contact margin but not touching
                continue
            other = point[2]
            if other in self._walls:
                wall = True
            elif other in self._wanderer_index:
                wanderers.add(self._wanderer_index[other])
            depth = max(depth, -distance)
        return wall, wanderers, depth

    def wanderer_contact(self, index):
        """
        Return the Husky's deepest contact with one wanderer, from the last collision detection.

        Parameters
        ----------
        index : int
            The wanderer.

        Returns
        -------
        ((float, float), (float, float)) or None
            The contact point on the Husky [m] and the contact normal in the plane, pointing
            from the wanderer towards the Husky (unit length); None when they do not
            penetrate, or the normal has no horizontal part.

        """
        deepest = None
        for point in pybullet.getContactPoints(bodyA=self.husky,
                                               bodyB=self.wanderer_bodies[index],
                                               physicsClientId=self.client):
            if point[8] < 0.0 and (deepest is None or point[8] < deepest[8]):
                deepest = point
        if deepest is None:
            return None
        nx, ny = deepest[7][0], deepest[7][1]        # contactNormalOnB: from B towards A
        norm = math.hypot(nx, ny)
        if norm < 1e-6:
            return None
        return (deepest[5][0], deepest[5][1]), (nx / norm, ny / norm)

    def _robot_body(self, body):
        """Load the robot's URDF, or make a box of its footprint standing on the ground."""
        client = self.client
        if body.urdf:
            return pybullet.loadURDF(os.path.join(pybullet_data.getDataPath(), body.urdf),
                                     flags=pybullet.URDF_MERGE_FIXED_LINKS,
                                     physicsClientId=client)
        half = (0.5 * body.length, 0.5 * body.width, 0.5 * body.height)
        shape = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=half,
                                              collisionFramePosition=(0.0, 0.0, half[2]),
                                              physicsClientId=client)
        # A mass, so that Bullet reports its contacts with the static walls.
        return pybullet.createMultiBody(baseMass=1.0, baseCollisionShapeIndex=shape,
                                        physicsClientId=client)

    def _agent_urdfs(self, n_wanderers):
        """Return each wanderer's URDF: ``agent_urdf``, or its items one per wanderer."""
        if isinstance(self._agent_urdf, (str, Path)):
            return [self._agent_urdf] * n_wanderers
        urdfs = list(self._agent_urdf)
        if len(urdfs) != n_wanderers:
            raise ValueError(f'{len(urdfs)} agent URDFs for {n_wanderers} wanderers')
        return urdfs

    def _mesh_shape(self, vertices, triangles):
        return pybullet.createCollisionShape(
            pybullet.GEOM_MESH, vertices=vertices.tolist(), indices=triangles.ravel().tolist(),
            flags=pybullet.GEOM_FORCE_CONCAVE_TRIMESH, physicsClientId=self.client)

    def _ray_body(self, shape, group, gui):
        """Create a static body of a mesh shape that only the rays meet, unseen in the GUI."""
        body = pybullet.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=shape,
                                        physicsClientId=self.client)
        pybullet.setCollisionFilterGroupMask(body, -1, group, RAY_GROUP,
                                             physicsClientId=self.client)
        if gui:
            pybullet.changeVisualShape(body, -1, rgbaColor=[0.0, 0.0, 0.0, 0.0],
                                       physicsClientId=self.client)
        return body

    def close(self):
        """Disconnect the client (again is harmless)."""
        if self.client is not None and self.client >= 0:
            pybullet.disconnect(physicsClientId=self.client)
        self.client = None


@contextmanager
def _quiet_native_output():
    """Silence C-level stdout and stderr (pybullet's URDF importer warnings) for a with block."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        os.dup2(null, 2)
        yield
    finally:
        for fd, copy in zip((1, 2), saved):
            os.dup2(copy, fd)
            os.close(copy)
        os.close(null)


#: A pedestrian's height [m].
PEDESTRIAN_HEIGHT = 1.7
_PEDESTRIAN_URDF = """<?xml version="1.0"?>
<!-- A pedestrian for sim_bridge: an upright cylinder, written by scene.agent_urdf. -->
<robot name="pedestrian">
  <link name="base_link">
    <inertial>
      <origin xyz="0 0 {half}" rpy="0 0 0"/>
      <mass value="70.0"/>
      <inertia ixx="1.0" ixy="0" ixz="0" iyy="1.0" iyz="0" izz="1.0"/>
    </inertial>
    <collision>
      <origin xyz="0 0 {half}" rpy="0 0 0"/>
      <geometry>
        <cylinder radius="{radius}" length="{height}"/>
      </geometry>
    </collision>
  </link>
</robot>
"""


def agent_urdf(config):
    """
    Return the URDF of the agents a `WandererConfig` describes.

    The P3-AT's file for ``body='p3at'``; for ``'cylinder'`` a one-link cylinder of the
    config's radius and `PEDESTRIAN_HEIGHT`, written once per radius into a folder under the
    system's temporary directory (its text depends on the radius alone).
    """
    if config.body == 'p3at':
        return P3AT_URDF
    import tempfile
    folder = Path(tempfile.gettempdir()) / 'sim_bridge_agents'
    folder.mkdir(exist_ok=True)
    path = folder / f'pedestrian_r{config.radius:.4f}.urdf'
    text = _PEDESTRIAN_URDF.format(radius=f'{config.radius:.4f}', height=PEDESTRIAN_HEIGHT,
                                   half=PEDESTRIAN_HEIGHT / 2.0)
    if not path.is_file() or path.read_text() != text:
        partial = path.with_suffix(f'.{os.getpid()}.tmp')
        partial.write_text(text)
        os.replace(partial, path)
    return path
