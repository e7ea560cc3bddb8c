"""Dataclass fields that carry their own description, unit, range or choices.

A parameter dataclass declares each field once, with what a user needs to know about it; its
``__post_init__`` calls :func:`validate_fields`, and the nodes build their ROS parameter
descriptors from the same metadata (biped_planner.node_support.dataclass_parameters), so the
library's bounds and the node's ranges cannot drift apart.

Example::

    @dataclass(frozen=True)
    class Gains:
        kp: float = parameter(3.0, 'DCM feedback gain (1)', low=0.0, high=20.0)
        mode: str = parameter('closed', 'loop mode', choices=('closed', 'open'))

        def __post_init__(self):
            validate_fields(self, ConfigError)
"""
import dataclasses
import math
import numbers
from typing import Optional, Sequence, Tuple

from biped_planner.input_checks import is_finite_number

_KEY = 'biped_parameter'


@dataclasses.dataclass(frozen=True)
class FieldSpec:
    """What a parameter field allows.

    :param description: meaning and unit, for users and ROS parameter descriptors
    :param low: lowest allowed number (None: unbounded); for tuples, each element
    :param high: highest allowed number (None: unbounded)
    :param low_open: low itself is not allowed
    :param choices: allowed values of a string field (None: any)
    """

    description: str
    low: Optional[float] = None
    high: Optional[float] = None
    low_open: bool = False
    choices: Optional[Tuple[str, ...]] = None

    @property
    def bounds(self):
        """(low, high) with infinite ends for missing limits, the choices, or None."""
        if self.choices is not None:
            return tuple(self.choices)
        if self.low is None and self.high is None:
            return None
        return (-math.inf if self.low is None else self.low,
                math.inf if self.high is None else self.high)


def parameter(default, description: str, low: Optional[float] = None,
              high: Optional[float] = None, low_open: bool = False,
              choices: Optional[Sequence[str]] = None):
    """A dataclass field with its FieldSpec in the field's metadata."""
    spec = FieldSpec(description, low, high, low_open,
                     tuple(choices) if choices is not None else None)
    return dataclasses.field(default=default, metadata={_KEY: spec})


def field_spec(field: dataclasses.Field) -> Optional[FieldSpec]:
    """The FieldSpec of a dataclass field, None for a field declared without parameter()."""
    return field.metadata.get(_KEY)


def field_specs(cls) -> dict:
    """{field name: FieldSpec} of every parameter() field of a dataclass (class or instance)."""
    return {f.name: field_spec(f) for f in dataclasses.fields(cls) if field_spec(f) is not None}


def _check_number(owner: str, name: str, value, spec: FieldSpec, error,
                  integer: bool = False) -> None:
    if not is_finite_number(value):
        raise error(f'{owner}.{name} must be a finite number, got {value!r}')
    if integer and not isinstance(value, numbers.Integral):
        raise error(f'{owner}.{name} must be an integer, got {value!r}')
    low, high = spec.low, spec.high
    if (low is not None and (value < low or (spec.low_open and value == low))) or (
            high is not None and value > high):
        bracket = '(' if spec.low_open else '['
        raise error(f'{owner}.{name} must be in {bracket}{low}, {high}], got {value!r}')


def validate_fields(instance, error=ValueError) -> None:
    """Check every parameter() field of a dataclass instance against its spec.

    Numbers must be finite and in range (bools are not numbers; a tuple is checked element by
    element), fields annotated ``int`` integers, strings one of their choices, bools bools.

    :param instance: the dataclass instance
    :param error: exception type to raise (the package's ConfigError)
    :raises error: naming the field, the value and what is allowed
    """
    owner = type(instance).__name__
    for field in dataclasses.fields(instance):
        spec = field_spec(field)
        if spec is None:
            continue
        value = getattr(instance, field.name)
        if spec.choices is not None:
            if value not in spec.choices:
                raise error(f'{owner}.{field.name} must be one of {spec.choices}, got {value!r}')
        elif isinstance(field.default, bool):
            if not isinstance(value, bool):
                raise error(f'{owner}.{field.name} must be a bool, got {value!r}')
        elif isinstance(value, tuple):
            for element in value:
                _check_number(owner, field.name, element, spec, error)
        else:
            _check_number(owner, field.name, value, spec, error,
                          integer=field.type in (int, 'int'))
