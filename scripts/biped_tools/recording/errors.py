"""The recorder's one error type."""


class RecordError(Exception):
    """A topic or type cannot be recorded, or the bag cannot be written."""
