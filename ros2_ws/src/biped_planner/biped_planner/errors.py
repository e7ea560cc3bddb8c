"""Exceptions of biped_planner: one base class, one subclass per kind of failure."""


class BipedPlannerError(Exception):
    """Base class of every error raised by biped_planner."""


class ConfigError(BipedPlannerError, ValueError):
    """A parameter is out of its allowed range or inconsistent with another."""


class MapError(BipedPlannerError, ValueError):
    """An occupancy grid is malformed (shape, resolution, values)."""


class PlanningError(BipedPlannerError):
    """No plan can be made: start or goal outside the map or occupied, or no path."""


class CommandError(BipedPlannerError, ValueError):
    """A walk command is malformed (NaN, out of range, unknown mode)."""
