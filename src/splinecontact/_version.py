"""The package version: the single source read by the build (``pyproject.toml``) and the code."""

__version__ = "0.2.0"
