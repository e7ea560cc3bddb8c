"""Every node refuses parameter values out of range, at start-up and live."""
import pytest
from rclpy.exceptions import InvalidParameterValueException
from rclpy.parameter import Parameter

from biped_mpc.nodes.mpc_controller import MpcControllerNode
from biped_planner.nodes.footstep_planner import FootstepPlannerNode
from biped_planner.nodes.reference_generator import ReferenceGeneratorNode
from biped_planner.nodes.state_machine import StateMachineNode
from biped_sim.nodes.simulator import SimulatorNode

BAD_AT_START = [
    (FootstepPlannerNode, 'path.step_length', -0.1),
    (FootstepPlannerNode, 'inflation.scale', 0.5),
    (FootstepPlannerNode, 'teleop.max_step_angle', 3.0),
    (ReferenceGeneratorNode, 'com_height', -1.0),
    (ReferenceGeneratorNode, 'support_scale', 2.0),
    (MpcControllerNode, 'feedback_gain', 2.0),
    (MpcControllerNode, 'model', 'banana'),
    (MpcControllerNode, 'pelvis_source', 'gps'),
    (StateMachineNode, 'single_support', 0.0),
    (SimulatorNode, 'backend', 'banana'),
    (SimulatorNode, 'camera.fps', 0.0),
    (SimulatorNode, 'terrain.kind', 5),
    (MpcControllerNode, 'solver', 'banana'),
    (MpcControllerNode, 'leg_outputs', 'sideways'),
    (StateMachineNode, 'update_rate', 0.0),
    (ReferenceGeneratorNode, 'horizon', 1),
    (FootstepPlannerNode, 'teleop_lookahead', -1),
]


@pytest.mark.parametrize('node_class, name, value', BAD_AT_START,
                         ids=[f'{c.__name__}-{n}' for c, n, _ in BAD_AT_START])
def test_a_bad_value_at_start_up_is_refused_naming_the_parameter(ros_context, node_class,
                                                                name, value):
    with pytest.raises((InvalidParameterValueException, ValueError)) as error:
        node_class(context=ros_context, parameter_overrides=[Parameter(name, value=value)])
    assert name.split('.')[-1] in str(error.value) or value in str(error.value) or \
        str(value) in str(error.value)


LIVE = [
    (FootstepPlannerNode, 'limits.max_step_length', 5.0, False),
    (FootstepPlannerNode, 'limits.max_step_length', 0.25, True),
    (ReferenceGeneratorNode, 'swing_height', -0.1, False),
    (MpcControllerNode, 'tilt_gain', 0.3, False),  # the controller cannot change while running
    (StateMachineNode, 'fall.max_tilt', 0.5, True),
    (SimulatorNode, 'real_time_factor', 0.0, False),
    (SimulatorNode, 'real_time_factor', 2.0, True),
    (MpcControllerNode, 'solver', 'banana', False),
]


@pytest.mark.parametrize('node_class, name, value, accepted', LIVE,
                         ids=[f'{c.__name__}-{n}-{v}' for c, n, v, _ in LIVE])
def test_live_changes_are_accepted_only_in_range_and_when_honoured(executor, ros_context,
                                                                   node_class, name, value,
                                                                   accepted):
    node = executor.track(node_class(context=ros_context))
    result = node.set_parameters([Parameter(name, value=value)])[0]
    assert result.successful == accepted
    if not accepted:
        assert result.reason


@pytest.mark.parametrize('node_class', [FootstepPlannerNode, ReferenceGeneratorNode,
                                        MpcControllerNode, StateMachineNode, SimulatorNode])
def test_every_parameter_has_a_description(executor, ros_context, node_class):
    node = executor.track(node_class(context=ros_context))
    names = [n for n in node._parameters if n != 'use_sim_time']
    described = node.describe_parameters(names)
    assert names and all(d.description for d in described), \
        [n for n, d in zip(names, described) if not d.description]


READ_ONLY = [
    (MpcControllerNode, 'solver', True),
    (MpcControllerNode, 'tilt_gain', True),
    (MpcControllerNode, 'stale_timeout', False),
    (SimulatorNode, 'backend', True),
    (SimulatorNode, 'real_time_factor', False),
    (ReferenceGeneratorNode, 'com_height', True),
    (ReferenceGeneratorNode, 'horizon', True),
]


@pytest.mark.parametrize('node_class, name, read_only', READ_ONLY,
                         ids=[f'{c.__name__}-{n}' for c, n, _ in READ_ONLY])
def test_parameters_read_at_start_only_are_declared_read_only(executor, ros_context,
                                                              node_class, name, read_only):
    node = executor.track(node_class(context=ros_context))
    assert node.describe_parameters([name])[0].read_only == read_only
    result = node.set_parameters([Parameter(name, value=node.get_parameter(name).value)])[0]
    assert result.successful != read_only
    if read_only:
        assert 'read-only' in result.reason and name in result.reason
