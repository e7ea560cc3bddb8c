"""Exceptions of biped_mpc: one base class, one subclass per kind of failure."""


class BipedMpcError(Exception):
    """Base class of every error raised by biped_mpc."""


class ConfigError(BipedMpcError, ValueError):
    """A parameter is out of its allowed range or inconsistent with another."""


class InputError(BipedMpcError, ValueError):
    """A reference or measurement has the wrong shape or is not finite."""


class SolverUnavailableError(BipedMpcError, ImportError):
    """A QP solver backend was requested whose Python package is not installed."""
