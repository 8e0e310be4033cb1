"""
The ``dpn`` node as a managed (lifecycle) node, as Nav2's servers are.

``rclpy.lifecycle.LifecycleNode`` gives the node the standard services under its name
(``<node>/change_state``, ``get_state``, ``get_available_states``,
``get_available_transitions``, ``get_transition_graph``) and the ``transition_event`` topic,
which ``nav2_lifecycle_manager`` drives. What each state means for dpn:

- **unconfigured** and **inactive**: scans and goals are ignored (the map keeps what it had),
  the action server refuses goals, no command is sent, the watchdog is quiet;
- **configure**: nothing to build (publishers, subscriptions and the grid exist from the
  start); **cleanup**: the goal and the map are cleared;
- **activate**: scans are mapped, goals taken and commands sent;
- **deactivate** (and **shutdown** from active): the goal is dropped and one zero command sent,
  so the robot stops.

``autostart`` (default true) configures and activates the node at start, so a bare
``ros2 run`` behaves as before. Under ``nav2_lifecycle_manager`` set ``autostart: false`` on
dpn, and ``bond_timeout: 0.0`` on the manager: the manager bonds with each node by default
(``bondcpp``), and dpn makes no bond (there is no bond library on the PyPI path), so with a bond
timeout the manager would report dpn unreachable after activating it.

"""

from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.lifecycle import LifecycleNodeMixin, TransitionCallbackReturn

RCLError = rclpy_implementation.RCLError


class ManagedNavigator:
    """
    Lifecycle callbacks of the ``dpn`` node; mixed in before ``LifecycleNode``.

    The node provides ``active`` (a flag its callbacks check), ``stop()`` (drop the goal, send
    a zero command), ``clear_map()``, ``navigate`` (the action server or None) and
    ``publish_status()``.

    """

    def _LifecycleNodeMixin__on_change_state(self, request, response):
        """
        Answer ``change_state``; a transition invalid in the current state is refused.

        rclpy's own callback raises on a transition the state machine does not have from the
        current state (``RCLError: Transition is not registered``), which would end the node;
        here it is answered with ``success: false`` and a warning, as rclcpp does.
        """
        try:
            return LifecycleNodeMixin._LifecycleNodeMixin__on_change_state(self, request,
                                                                           response)
        except RCLError as error:
            self.get_logger().warning(
                f'change_state refused: transition {request.transition.id} '
                f'{request.transition.label!r} from {self._state_machine.current_state[1]!r}: '
                f'{error}')
            response.success = False
            return response

    def _set_active(self, active):
        self.active = active
        stop_guard = getattr(self, 'stop_guard', None)
        if stop_guard is not None:
            stop_guard.enabled = active
        if not active:
            self.pending_scans.clear()
        if self.navigate is not None:
            self.navigate.enabled = active
            if not active:
                self.navigate.preempt('the navigator was deactivated')
        self.publish_status()

    def on_configure(self, state):
        """Nothing to build: configured."""
        self.get_logger().info('configured')
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        """Map, take goals and command from now on."""
        self._set_active(True)
        self.get_logger().info('active')
        return TransitionCallbackReturn.SUCCESS

    def on_deactivate(self, state):
        """Stop the robot and ignore scans and goals."""
        self.stop()
        self._set_active(False)
        self.get_logger().info('inactive: robot stopped')
        return TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state):
        """Forget the goal and the map."""
        self.clear_map()
        self.get_logger().info('cleaned up: goal and map cleared')
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state):
        """Stop the robot (from any state)."""
        self.stop()
        self._set_active(False)
        return TransitionCallbackReturn.SUCCESS

    def on_error(self, state):
        """Stop the robot; the node goes to unconfigured."""
        self.stop()
        self._set_active(False)
        return TransitionCallbackReturn.SUCCESS
