"""``python -m pds_plugin.cli``: the ``pds-mesh`` command."""

from . import console

console()
