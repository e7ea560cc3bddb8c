"""ROS parameters from a frozen parameter dataclass: one parameter per field.

The dataclass stays the source of truth (defaults, units, validation in __post_init__); this module
declares each field with a ParameterDescriptor (description and range), builds the dataclass from
the values, and rejects live changes that the dataclass refuses. Shared by the nodes of every
biped package.
"""
import dataclasses
import math
from typing import Callable, Dict, Iterable, Optional, Tuple, Type, TypeVar

from rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,
                                SetParametersResult)
from rclpy.node import Node

from biped_planner.parameter_fields import field_specs

T = TypeVar('T')
# field name -> (description with unit, (low, high) or None)
ParameterSpecs = Dict[str, Tuple[str, Optional[Tuple[float, float]]]]


def _descriptor(name: str, value, description: str, bounds,
                read_only: bool = False) -> ParameterDescriptor:
    descriptor = ParameterDescriptor(name=name, description=description, read_only=read_only)
    if bounds is None or isinstance(value, bool):
        return descriptor
    if all(isinstance(b, str) for b in bounds):
        descriptor.description = f'{description}; one of {", ".join(bounds)}'
        return descriptor
    low, high = bounds
    if isinstance(value, int) and math.isfinite(low) and math.isfinite(high):
        descriptor.integer_range = [IntegerRange(from_value=int(low), to_value=int(high), step=1)]
    elif isinstance(value, float) and math.isfinite(low) and math.isfinite(high):
        descriptor.floating_point_range = [
            FloatingPointRange(from_value=float(low), to_value=float(high), step=0.0)]
    return descriptor


def declare_dataclass_parameters(node: Node, defaults: T, specs: ParameterSpecs,
                                 prefix: str = '',
                                 on_change: Optional[Callable[[T], None]] = None,
                                 fixed: Optional[dict] = None) -> T:
    """Declare one parameter per dataclass field and return the dataclass built from them.

    :param node: the node that owns the parameters
    :param defaults: a dataclass instance whose values are the defaults
    :param specs: description (with unit) and allowed range of each field that is not declared
        with biped_planner.parameter_fields.parameter (those carry their own)
    :param prefix: parameter name prefix, e.g. 'timing.' (empty: the field names)
    :param on_change: called with the new dataclass after an accepted live change; None
        declares the parameters read-only (the node cannot honour a live change: rclpy refuses
        it, naming the parameter)
    :param fixed: values of fields that are not parameters (e.g. nested dataclasses)
    :return: the dataclass built from the declared values
    :raises ValueError: when the values given at start-up are refused by the dataclass
    """
    cls: Type[T] = type(defaults)
    fixed = dict(fixed or {})
    names = [f.name for f in dataclasses.fields(cls) if f.name not in fixed]
    specs = {**{name: (spec.description, spec.bounds)
                for name, spec in field_specs(cls).items()}, **specs}
    missing = [n for n in names if n not in specs]
    if missing:
        raise KeyError(f'no parameter description for {cls.__name__} fields {missing}')
    for name in names:
        value = getattr(defaults, name)
        if isinstance(value, tuple):
            value = [float(v) for v in value]
        elif isinstance(value, int) and not isinstance(value, bool):
            value = int(value)
        description, bounds = specs[name]
        node.declare_parameter(prefix + name, value, _descriptor(
            prefix + name, value, description, bounds, read_only=on_change is None))
    current = _build(cls, node, names, prefix, {}, fixed)
    if on_change is None:
        return current

    def on_set(parameters) -> SetParametersResult:
        changes = {p.name[len(prefix):]: p.value for p in parameters
                   if p.name.startswith(prefix) and p.name[len(prefix):] in names}
        if not changes:
            return SetParametersResult(successful=True)
        try:
            updated = _build(cls, node, names, prefix, changes, fixed)
        except (ValueError, TypeError) as error:
            return SetParametersResult(successful=False, reason=str(error))
        on_change(updated)
        return SetParametersResult(successful=True)

    node.add_on_set_parameters_callback(on_set)
    return current


def declare_live_parameters(node: Node, defaults: T, prefix: str, attribute: str) -> T:
    """Declare the fields of a dataclass that carries its own specs, and keep
    node.<attribute> the dataclass of their current values (live changes included).

    :return: the dataclass built from the declared values
    """
    value = declare_dataclass_parameters(node, defaults, {}, prefix=prefix,
                                         on_change=lambda p: setattr(node, attribute, p))
    setattr(node, attribute, value)
    return value


def _build(cls, node: Node, names, prefix: str, overrides: dict, fixed: dict):
    values = dict(fixed)
    for name in names:
        value = overrides.get(name, node.get_parameter(prefix + name).value)
        if isinstance(value, list):
            value = tuple(value)
        values[name] = value
    return cls(**values)


# name -> (default, description with unit, (low, high) for numbers, a tuple of allowed strings,
# or None)
NodeParameterSpecs = Dict[str, Tuple[object, str, Optional[tuple]]]


def declare_node_parameters(node: Node, specs: NodeParameterSpecs,
                            read_only: Iterable[str] = ()) -> None:
    """Declare a node's own parameters (those not from a dataclass) with descriptions and ranges.

    Numeric ranges go into the descriptor, so rclpy refuses out-of-range values at start-up and
    in live changes; string choices are checked here, at start-up and on every live change.

    :param read_only: names of the parameters read at start only: declared read-only, so that
        rclpy refuses a live change of them

    :raises ValueError: when a start-up value is not one of its allowed strings
    """
    read_only = set(read_only)
    unknown = read_only - set(specs)
    if unknown:
        raise KeyError(f'read_only names parameters not in specs: {sorted(unknown)}')
    choices = {}
    for name, (default, description, bounds) in specs.items():
        if bounds is not None and all(isinstance(b, str) for b in bounds):
            choices[name] = tuple(bounds)
            bounds = None
            description = f'{description}; one of {", ".join(choices[name])}'
        node.declare_parameter(name, default, _descriptor(name, default, description, bounds,
                                                          read_only=name in read_only))
        if name in choices and node.get_parameter(name).value not in choices[name]:
            raise ValueError(f'parameter {name} = {node.get_parameter(name).value!r} must be one '
                             f'of {choices[name]}')

    def on_set(parameters) -> SetParametersResult:
        for parameter in parameters:
            if parameter.name in choices and parameter.value not in choices[parameter.name]:
                return SetParametersResult(successful=False, reason=(
                    f'{parameter.name} must be one of {choices[parameter.name]}'))
        return SetParametersResult(successful=True)

    if choices:
        node.add_on_set_parameters_callback(on_set)
