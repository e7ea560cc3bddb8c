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


class FrameError(CommandError):
    """A command or message is expressed in another frame than the expected one."""


class InputError(BipedPlannerError, ValueError):
    """A message from another node is malformed or physically impossible."""


class SolverUnavailableError(BipedPlannerError, ImportError):
    """A solver was requested whose Python package is not installed."""


class StartOutsideMapError(PlanningError):
    """The start lies outside the map."""


class GoalOutsideMapError(PlanningError):
    """The goal lies outside the map."""


class StartOccupiedError(PlanningError):
    """The start lies in an obstacle or in its inflated margin."""


class GoalOccupiedError(PlanningError):
    """The goal lies in an obstacle or in its inflated margin."""


class NoPathError(PlanningError):
    """No collision-free path joins the start and the goal."""
