"""Exceptions of biped_sim: one base class, one subclass per kind of failure."""


class BipedSimError(Exception):
    """Base class of every error raised by biped_sim."""


class ConfigError(BipedSimError, ValueError):
    """A parameter is out of its allowed range or inconsistent with another."""


class InputError(BipedSimError, ValueError):
    """A run-time input of the model plant (state, jerk, force, time step) is malformed."""


class RobotModelError(BipedSimError):
    """A robot description does not match its URDF (missing joint, link or frame)."""
