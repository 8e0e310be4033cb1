"""
The ``dpn`` node's lifecycle, driven over DDS the way nav2_lifecycle_manager drives it.

The manager calls ``<node>/change_state`` with configure then activate at start-up, and
deactivate, cleanup and shutdown at the end, checking ``<node>/get_state`` in between.
"""

import time

from dpn_navigator.ros.dpn_node import DpnNode
from lifecycle_msgs.msg import State, Transition
from lifecycle_msgs.srv import ChangeState, GetState
from node_harness import executor_for
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from sim_stand_in import SimulatorStandIn

STREAMS = ('clock', 'odometry', 'scan')


class Manager(Node):
    """The service calls of nav2_lifecycle_manager."""

    def __init__(self, context):
        super().__init__('lifecycle_manager_stand_in', context=context)
        self.change = self.create_client(ChangeState, '/compabot/dpn/change_state')
        self.get = self.create_client(GetState, '/compabot/dpn/get_state')


def run(executor, sim, seconds=None, until=None):
    end = time.monotonic() + (seconds if seconds is not None else 10.0)
    while time.monotonic() < end:
        sim.tick(STREAMS)
        executor.spin_once(timeout_sec=0.02)
        if until is not None and until():
            return True
    return until is None


def call(executor, sim, client, request):
    future = client.call_async(request)
    assert run(executor, sim, until=future.done)
    return future.result()


def transition(executor, sim, manager, transition_id):
    request = ChangeState.Request()
    request.transition.id = transition_id
    return call(executor, sim, manager.change, request).success


def state(executor, sim, manager):
    return call(executor, sim, manager.get, GetState.Request()).current_state.id


def moving(sim, since):
    return [c for c in sim.commands if c[0] >= since and (c[1] != 0.0 or c[2] != 0.0)]


@pytest.fixture
def managed(ros_context):
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
        Parameter('laser_x', value=0.0), Parameter('use_sim_time', value=True),
        Parameter('autostart', value=False), Parameter('use_default_goal', value=True),
        Parameter('goal_x', value=9.0), Parameter('goal_y', value=6.0)])
    sim = SimulatorStandIn(ros_context)
    manager = Manager(ros_context)
    with executor_for(ros_context, dpn, sim, manager) as executor:
        assert run(executor, sim, until=lambda: manager.change.service_is_ready()
                   and manager.get.service_is_ready())
        yield dpn, sim, manager, executor


def test_transitions_as_the_lifecycle_manager_drives_them(managed):
    dpn, sim, manager, executor = managed
    assert state(executor, sim, manager) == State.PRIMARY_STATE_UNCONFIGURED
    run(executor, sim, seconds=1.0)
    assert moving(sim, 0.0) == [] and not np.any(dpn.navigator.grid.labels)
    assert transition(executor, sim, manager, Transition.TRANSITION_CONFIGURE)
    assert state(executor, sim, manager) == State.PRIMARY_STATE_INACTIVE
    run(executor, sim, seconds=0.5)
    assert moving(sim, 0.0) == []                       # inactive: no command
    assert transition(executor, sim, manager, Transition.TRANSITION_ACTIVATE)
    assert state(executor, sim, manager) == State.PRIMARY_STATE_ACTIVE
    activated = time.monotonic()
    run(executor, sim, seconds=1.0)
    assert moving(sim, activated)                       # the default goal drives it
    assert np.any(dpn.navigator.grid.labels)
    deactivate_sent = time.monotonic()
    assert transition(executor, sim, manager, Transition.TRANSITION_DEACTIVATE)
    assert state(executor, sim, manager) == State.PRIMARY_STATE_INACTIVE
    run(executor, sim, seconds=1.0)
    # A zero command, and none but zero after it (commands already in flight may land first).
    stopped = next(t for t, v, w in sim.commands if t >= deactivate_sent and v == w == 0.0)
    assert stopped - deactivate_sent < 0.5
    assert moving(sim, stopped) == []
    assert dpn.navigator.goal is None
    assert transition(executor, sim, manager, Transition.TRANSITION_CLEANUP)
    assert state(executor, sim, manager) == State.PRIMARY_STATE_UNCONFIGURED
    assert not np.any(dpn.navigator.grid.labels)        # the map was cleared
    assert transition(executor, sim, manager, Transition.TRANSITION_UNCONFIGURED_SHUTDOWN)
    assert state(executor, sim, manager) == State.PRIMARY_STATE_FINALIZED


def test_an_invalid_transition_is_refused(managed):
    dpn, sim, manager, executor = managed
    assert not transition(executor, sim, manager, Transition.TRANSITION_ACTIVATE)
    assert state(executor, sim, manager) == State.PRIMARY_STATE_UNCONFIGURED


def test_autostart_activates_at_once(ros_context):
    dpn = DpnNode(context=ros_context, namespace='auto', parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=12.0)])
    try:
        assert dpn.active
        assert dpn._state_machine.current_state[1] == 'active'
    finally:
        dpn.destroy_node()
