"""
Both nodes refuse parameters they did not declare, ``''`` included, over their services.

rclpy's own check lets a parameter named ``''`` through ``set_parameters`` (it tests the names
with ``any()``) and reports other undeclared names as ``[]``; the nodes check the names
themselves (``parameter_declaration.refuse_undeclared_parameters``). Asked over DDS, with
rclpy's parameter client, as ``ros2 param set`` does.
"""

from dpn_navigator.ros.dpn_node import DpnNode
from node_harness import executor_for
import pytest
from rcl_interfaces.msg import ParameterType
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from sim_bridge.pybullet_world_node import PybulletWorldNode


def call(executor, future, timeout=10.0):
    executor.spin_until_future_complete(future, timeout_sec=timeout)
    assert future.done(), 'no answer from the parameter service'
    return future.result()


@pytest.fixture(params=['dpn', 'pybullet_world'])
def served_node(request, ros_context):
    if request.param == 'dpn':
        node = DpnNode(context=ros_context, parameter_overrides=[
            Parameter('map_width', value=12.0), Parameter('map_height', value=12.0)])
    else:
        node = PybulletWorldNode(context=ros_context,
                                 parameter_overrides=[Parameter('wanderers', value=0)])
    asker = Node('parameter_asker', context=ros_context)
    client = AsyncParameterClient(asker, node.get_fully_qualified_name())
    with executor_for(ros_context, node, asker) as executor:
        assert client.wait_for_services(timeout_sec=10.0)
        yield node, client, executor


@pytest.mark.parametrize('names', [[''], ['no_such_parameter'], ['', 'no_such_parameter']])
def test_undeclared_names_are_refused_with_a_reason_that_names_them(served_node, names):
    node, client, executor = served_node
    before = set(node._parameters)
    parameters = [Parameter(name, value=1.0) for name in names]
    results = call(executor, client.set_parameters(parameters)).results
    assert len(results) == len(names)
    for name, result in zip(names, results):
        assert not result.successful
        assert 'undeclared' in result.reason and repr(name) in result.reason, result.reason
    atomic = call(executor, client.set_parameters_atomically(parameters)).result
    assert not atomic.successful
    for name in names:
        assert repr(name) in atomic.reason, atomic.reason
    assert set(node._parameters) == before
    listed = call(executor, client.list_parameters()).result.names
    assert '' not in listed and 'no_such_parameter' not in listed
    got = call(executor, client.get_parameters(['']))
    assert all(value.type == ParameterType.PARAMETER_NOT_SET for value in got.values)


def test_a_declared_parameter_is_still_answered(served_node):
    node, client, executor = served_node
    result = call(executor, client.set_parameters([Parameter('use_sim_time', value=False)]))
    assert [r.successful for r in result.results] == [True], result.results
