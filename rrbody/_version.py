"""The package version: the one name any module may import from the rrbody root."""

__version__ = "0.1.0"
