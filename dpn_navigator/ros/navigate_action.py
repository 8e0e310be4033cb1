"""
The Nav2 navigation interface of the ``dpn`` node: the ``navigate_to_pose`` action server.

Type ``nav2_msgs/action/NavigateToPose`` (the real ``nav2_msgs`` on an apt install, the
``fallback/nav2_msgs`` stand-in with the same definition on the PyPI path), name relative to
the node's namespace (``/compabot/navigate_to_pose`` by default), as Nav2's bt_navigator serves
it. One goal at a time:

- **accept**: a goal in ``map_frame`` (an empty frame id means ``map_frame``) with finite
  coordinates inside the map becomes the navigator's goal; its orientation and
  ``behavior_tree`` are ignored (dpn reaches a position);
- **reject with a reason**: an off-map, non-finite or other-frame goal is accepted and at once
  aborted with ``error_code`` and ``error_msg`` in the result (a plain ROS 2 goal rejection
  carries no reason); the codes are Nav2 Jazzy's planner codes, which bt_navigator forwards
  (`GOAL_OUTSIDE_MAP` 204, `TF_ERROR` 202 for a frame other than the map's, `UNKNOWN` 200 for a
  non-finite goal);
- **preempt**: a new goal (or one on ``goal_pose``) ends the running one as aborted with
  ``error_msg`` 'preempted ...' and takes its place, as Nav2's preemption does;
- **cancel**: the robot is stopped in the cancel callback itself (the goal dropped, a zero
  command sent), the goal ends as canceled at the next tick (``FEEDBACK_PERIOD``);
- **succeed** when the navigator reports the goal reached;
- **feedback** every ``FEEDBACK_PERIOD`` (5 Hz): ``current_pose`` (the robot in
  ``map_frame``), ``navigation_time``, ``estimated_time_remaining`` (the path left at
  ``max_linear_speed``), ``number_of_recoveries`` (the navigator's forgets),
  ``distance_remaining`` (along the planned path, straight to the goal before there is one).

"""

from dataclasses import dataclass
import math

from builtin_interfaces.msg import Duration
from geometry_msgs.msg import PoseStamped
import numpy as np
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.clock import Clock, ClockType
from rclpy.task import Future

from .conversions import yaw_to_quaternion

#: Feedback and the checks of the running goal, on the steady clock [s].
FEEDBACK_PERIOD = 0.2
#: Error codes of nav2_msgs Jazzy's ComputePathToPose result, which bt_navigator forwards in
#: NavigateToPose's ``error_code`` (NavigateToPose itself defines only NONE = 0 in Jazzy).
NONE = 0
UNKNOWN = 200
TF_ERROR = 202
GOAL_OUTSIDE_MAP = 204


def load_action_type():
    """Return ``nav2_msgs.action.NavigateToPose``, or None when nav2_msgs is not installed."""
    try:
        from nav2_msgs.action import NavigateToPose
    except ImportError:
        return None
    return NavigateToPose


def seconds_to_duration(seconds):
    """Return a ``builtin_interfaces/Duration`` of ``seconds`` [s] (negative clamped to 0)."""
    nanoseconds = max(0, int(round(seconds * 1e9)))
    return Duration(sec=nanoseconds // 1_000_000_000, nanosec=nanoseconds % 1_000_000_000)


def distance_along(path_xy, position):
    """
    Return the length of ``path_xy`` left from its point nearest ``position`` [m].

    Parameters
    ----------
    path_xy : (N, 2) ndarray of float or None
        The planned path in the map frame [m].
    position : (float, float)
        The robot [m].

    Returns
    -------
    float or None
        None when there is no path.

    """
    if path_xy is None or len(path_xy) == 0:
        return None
    path_xy = np.asarray(path_xy, dtype=np.float64)
    nearest = int(np.argmin(np.hypot(path_xy[:, 0] - position[0],
                                     path_xy[:, 1] - position[1])))
    rest = path_xy[nearest:]
    return float(math.dist(position, rest[0]) + np.hypot(*np.diff(rest, axis=0).T).sum())


@dataclass
class ActiveGoal:
    """The running goal: its handle, the future its execute callback awaits, its start [s]."""

    handle: object
    done: Future
    started: float


class NavigateToPoseServer:
    """
    The ``navigate_to_pose`` action server of a ``DpnNode`` (see the module).

    Parameters
    ----------
    node : DpnNode
        Gives ``set_goal(x, y)`` (None, or the reason it refused), ``stop()``, ``pose``,
        ``navigator``, ``params`` and ``now_seconds()``.
    action_type : type
        ``nav2_msgs.action.NavigateToPose``.

    """

    def __init__(self, node, action_type):
        self.node = node
        self.action_type = action_type
        self.active = None
        self.enabled = True
        self.server = ActionServer(node, action_type, 'navigate_to_pose', self.execute,
                                   goal_callback=self.on_goal_request,
                                   cancel_callback=self.on_cancel)
        self.timer = node.create_timer(FEEDBACK_PERIOD, self.on_tick,
                                       clock=Clock(clock_type=ClockType.STEADY_TIME))

    def on_goal_request(self, goal_request):
        """Accept every goal while enabled (invalid ones end at once with a reason)."""
        return GoalResponse.ACCEPT if self.enabled else GoalResponse.REJECT

    def on_cancel(self, goal_handle):
        """Accept a cancel; stop the robot now if it is the running goal."""
        if self.active is not None and goal_handle is self.active.handle:
            self.node.stop()
        return CancelResponse.ACCEPT

    def check(self, pose_stamped):
        """Return ``(error_code, error_msg)`` for an unusable goal, or None."""
        map_frame = self.node.params.map_frame
        frame = pose_stamped.header.frame_id
        if frame not in ('', map_frame):
            return TF_ERROR, f'goal frame {frame!r} is not the map frame {map_frame!r}'
        position = pose_stamped.pose.position
        if not all(math.isfinite(v) for v in (position.x, position.y, position.z)):
            return UNKNOWN, 'goal position is not finite'
        return None

    def result(self, error_code=NONE, error_msg=''):
        """Return a ``NavigateToPose.Result``."""
        return self.action_type.Result(error_code=error_code, error_msg=error_msg)

    async def execute(self, goal_handle):
        """Run one goal until it succeeds, is canceled, preempted or refused."""
        request = goal_handle.request
        error = self.check(request.pose)
        if error is None:
            position = request.pose.pose.position
            reason = self.node.set_goal(position.x, position.y, via='navigate_to_pose')
            if reason is not None:
                error = (GOAL_OUTSIDE_MAP, reason)
        if error is not None:
            self.node.get_logger().warning(f'navigate_to_pose goal refused: {error[1]}')
            goal_handle.abort()
            return self.result(*error)
        self.preempt('preempted by a new navigate_to_pose goal')
        active = ActiveGoal(goal_handle, Future(), self.node.now_seconds())
        self.active = active
        state, error_code, error_msg = await active.done
        getattr(goal_handle, state)()
        return self.result(error_code, error_msg)

    def finish(self, state, error_code=NONE, error_msg=''):
        """End the running goal: ``state`` is ``'succeed'``, ``'abort'`` or ``'canceled'``."""
        active, self.active = self.active, None
        if active is not None and not active.done.done():
            active.done.set_result((state, error_code, error_msg))

    def preempt(self, reason):
        """End the running goal as aborted, because another one takes its place."""
        if self.active is not None:
            self.finish('abort', NONE, reason)

    def on_tick(self):
        """Finish a canceled or reached goal; send feedback on the running one."""
        active = self.active
        if active is None:
            return
        if active.handle.is_cancel_requested:
            self.node.stop()
            self.finish('canceled', NONE, 'canceled')
            return
        navigator = self.node.navigator
        if navigator.status.value == 'goal_reached':
            self.finish('succeed')
            return
        if navigator.goal is None:          # dropped (e.g. a deactivation)
            self.finish('abort', UNKNOWN, 'the goal was dropped')
            return
        active.handle.publish_feedback(self.feedback(active))

    def feedback(self, active):
        """Return the ``NavigateToPose.Feedback`` of the running goal."""
        node = self.node
        msg = self.action_type.Feedback()
        pose = node.pose
        goal = node.navigator.goal
        now = node.now_seconds()
        msg.navigation_time = seconds_to_duration(now - active.started)
        msg.number_of_recoveries = min(int(node.navigator.forgets), 32767)
        if pose is not None:
            current = PoseStamped()
            current.header.frame_id = node.params.map_frame
            current.header.stamp = node.get_clock().now().to_msg()
            current.pose.position.x, current.pose.position.y = float(pose[0]), float(pose[1])
            current.pose.orientation = yaw_to_quaternion(float(pose[2]))
            msg.current_pose = current
            remaining = distance_along(node.navigator.path_xy, pose[:2])
            if remaining is None and goal is not None:
                remaining = math.dist(pose[:2], goal)
            if remaining is not None:
                msg.distance_remaining = float(remaining)
                speed = node.params.navigator.follower.max_linear_speed
                msg.estimated_time_remaining = seconds_to_duration(remaining / speed)
        return msg

    def destroy(self):
        """Destroy the action server and its timer."""
        self.server.destroy()
        self.node.destroy_timer(self.timer)
