"""``python -m rrbody.cli``: the ``rrbody`` command."""

from rrbody.cli.main import entry

raise SystemExit(entry())
