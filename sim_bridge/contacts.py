"""
Count the Husky's collisions as distinct contact events, for judging an episode.

A contact event starts on the first tick the Husky touches something it did not touch on the
tick before, and lasts while the touching goes on. All walls together count as one obstacle,
so scraping along a wall made of several boxes, or into a corner, is one event; each wanderer
is an obstacle of its own.

**Who closed the gap.** A contact event with a wanderer is *agent-caused* when, on the tick it
starts, the Husky's surface at the contact moves towards the wanderer at no more than
`APPROACH_SPEED` (the Husky stood, or moved away or sideways) and slower than the wanderer's
surface there moves towards the Husky (the wanderer walked or turned into it); every other
contact is *robot-caused* (the Husky drove or turned into the wanderer, or both stood nearly
still and the Husky's own small motion made the touch). Each surface's speed is its body's
velocity at the contact point, turning included (``v + omega x r``), along the contact normal
(`robot_caused_at_contact`, from pybullet's deepest contact point). Judged by the centres
instead (`robot_caused`, kept for a contact pybullet gives no point for), a P3-AT box turning
its corner into a standing Husky has no approach of its own and was counted the Husky's, and
a Husky whose corner slid into a standing P3-AT while curving could be counted the P3-AT's.
This is the split of at-fault and not-at-fault collisions of nuPlan's
``no_ego_at_fault_collisions`` metric (Caesar et al. 2021, *nuPlan: A closed-loop ML-based
planning benchmark for autonomous vehicles*, arXiv:2106.11810; nuplan-devkit's
``CollisionType``: a collision with a stopped ego, ``STOPPED_EGO_COLLISION``, is not at
fault), made planar for a robot that turns in place. Wall contacts are all the robot's.

"""

import math

#: Speed of the Husky's nearest point towards a wanderer above which a new contact with it is
#: robot-caused [m/s] (the benchmark's standing-still threshold, ``still_time``).
APPROACH_SPEED = 0.05


def robot_caused(pose, velocity, length, width, point, point_velocity):
    """
    Tell whether a contact that starts now is the Husky's doing (see the module's rule).

    ``pose``, ``velocity``, ``length``, ``width`` and ``point`` as for `approach_speed`;
    ``point_velocity`` is the wanderer's velocity ``(vx, vy)`` [m/s] over the tick.
    """
    robot = approach_speed(pose, velocity, length, width, point)
    if robot > APPROACH_SPEED:
        return True
    # The wanderer's speed towards the Husky's centre side: its velocity against the
    # direction from the Husky to it, as `approach_speed` measures it.
    agent = approach_speed(pose, (0.0, 0.0), length, width, point,
                           point_velocity=point_velocity)
    return robot >= agent


def robot_caused_at_contact(pose, velocity, contact, normal, agent_centre, agent_velocity,
                            agent_yaw_rate):
    """
    Tell whether a contact that starts now is the Husky's doing, judged at the contact point.

    Parameters
    ----------
    pose : (float, float, float)
        The Husky's pose ``(x, y, yaw)``, its centre of rotation [m, m, rad].
    velocity : (float, float)
        Its forward speed and turn rate ``(v, omega)`` [m/s, rad/s].
    contact : (float, float)
        The contact point [m].
    normal : (float, float)
        The contact normal, pointing from the wanderer towards the Husky (unit length or not;
        not zero).
    agent_centre : (float, float)
        The wanderer's centre of rotation [m].
    agent_velocity : (float, float)
        Its velocity ``(vx, vy)`` over the tick [m/s].
    agent_yaw_rate : float
        Its turn rate over the tick [rad/s].

    Returns
    -------
    bool
        True when the Husky's surface at the contact moves towards the wanderer faster than
        `APPROACH_SPEED`, or at least as fast as the wanderer's surface moves towards it.

    """
    norm = math.hypot(normal[0], normal[1])
    if not norm > 0.0:
        raise ValueError(f'the contact normal must not be zero, got {normal!r}')
    nx, ny = normal[0] / norm, normal[1] / norm
    v, omega = velocity
    yaw = pose[2]
    rx, ry = contact[0] - pose[0], contact[1] - pose[1]
    husky_vx = v * math.cos(yaw) - omega * ry
    husky_vy = v * math.sin(yaw) + omega * rx
    robot = -(husky_vx * nx + husky_vy * ny)          # towards the wanderer: against the normal
    if robot > APPROACH_SPEED:
        return True
    ax, ay = contact[0] - agent_centre[0], contact[1] - agent_centre[1]
    agent_vx = agent_velocity[0] - agent_yaw_rate * ay
    agent_vy = agent_velocity[1] + agent_yaw_rate * ax
    agent = agent_vx * nx + agent_vy * ny             # towards the Husky: along the normal
    return robot >= agent


def approach_speed(pose, velocity, length, width, point, point_velocity=(0.0, 0.0)):
    """
    Return how fast the Husky's footprint point nearest ``point`` moves towards it [m/s].

    Parameters
    ----------
    pose : (float, float, float)
        The Husky's pose ``(x, y, yaw)``, its footprint's centre [m, m, rad].
    velocity : (float, float)
        Its forward speed and turn rate ``(v, omega)`` [m/s, rad/s].
    length, width : float
        Its footprint, a rectangle centred on the pose [m].
    point : (float, float)
        The other body's centre [m].
    point_velocity : (float, float)
        The other body's velocity [m/s]; its part is subtracted (default: standing).

    Returns
    -------
    float
        The velocity of the footprint's nearest point relative to ``point``'s, projected on
        the unit vector from that point to ``point`` (from the footprint's centre when
        ``point`` lies inside it); positive when closing in, 0 when ``point`` is the centre.

    """
    x, y, yaw = pose
    v, omega = velocity
    c, s = math.cos(yaw), math.sin(yaw)
    dx, dy = point[0] - x, point[1] - y
    # The point in the Husky's frame, clamped onto the footprint.
    along = min(max(c * dx + s * dy, -0.5 * length), 0.5 * length)
    side = min(max(-s * dx + c * dy, -0.5 * width), 0.5 * width)
    px, py = c * along - s * side, s * along + c * side  # nearest point, from the centre
    ux, uy = dx - px, dy - py
    norm = math.hypot(ux, uy)
    if norm < 1e-9:
        ux, uy = dx, dy
        norm = math.hypot(ux, uy)
        if norm < 1e-9:
            return 0.0
    vx = v * c - omega * py - point_velocity[0]
    vy = v * s + omega * px - point_velocity[1]
    return (vx * ux + vy * uy) / norm


class ContactLog:
    """
    Contact events of the Husky with walls and with wanderers.

    Attributes
    ----------
    wall_events : int
        Distinct contact events with walls.
    wanderer_events : int
        Distinct contact events with wanderers (a touch of two wanderers at once counts two).
    robot_caused_events, agent_caused_events : int
        The wanderer events the Husky caused (it moved towards the wanderer) and the ones the
        wanderer caused (the Husky stood or moved away); they add up to ``wanderer_events``.
    first_wall_time, first_wanderer_time : float or None
        Simulated time of the first event of each kind [s], None before it.
    touching_wall : bool
        Whether the Husky touches a wall now.
    touching_wanderers : frozenset of int
        Indices of the wanderers it touches now.

    """

    def __init__(self):
        self.wall_events = 0
        self.wanderer_events = 0
        self.robot_caused_events = 0
        self.agent_caused_events = 0
        self.first_wall_time = None
        self.first_wanderer_time = None
        self.touching_wall = False
        self.touching_wanderers = frozenset()

    @property
    def events(self):
        """Return the number of contact events, walls and wanderers together."""
        return self.wall_events + self.wanderer_events

    @property
    def first_contact_time(self):
        """Return the simulated time of the first contact of any kind [s], or None."""
        times = [t for t in (self.first_wall_time, self.first_wanderer_time) if t is not None]
        return min(times) if times else None

    def update(self, stamp, touching_wall, touching_wanderers, approached=None):
        """
        Record what the Husky touches on one tick.

        Parameters
        ----------
        stamp : float
            Simulated time of the tick [s].
        touching_wall : bool
            Whether it touches any wall.
        touching_wanderers : iterable of int
            Indices of the wanderers it touches.
        approached : container of int, optional
            The wanderers a new contact with which is robot-caused (`robot_caused`); any
            other new contact is agent-caused. Default: all of them.

        """
        touching_wanderers = frozenset(touching_wanderers)
        if touching_wall and not self.touching_wall:
            self.wall_events += 1
            if self.first_wall_time is None:
                self.first_wall_time = stamp
        new = touching_wanderers - self.touching_wanderers
        if new:
            self.wanderer_events += len(new)
            caused = len(new) if approached is None else sum(i in approached for i in new)
            self.robot_caused_events += caused
            self.agent_caused_events += len(new) - caused
            if self.first_wanderer_time is None:
                self.first_wanderer_time = stamp
        self.touching_wall = bool(touching_wall)
        self.touching_wanderers = touching_wanderers
