"""The ``rrbody`` command line (top layer): argument helpers, subcommands, batch mode, scene runner."""

from rrbody.cli.main import build_parser, entry, main

__all__ = ["main", "entry", "build_parser"]
