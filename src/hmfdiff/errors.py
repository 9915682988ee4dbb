"""Errors that name what is wrong, shared by the physics and the pipeline."""


class ConfigError(ValueError):
    """An invalid configuration value; the message names the case (or section) and the field."""
