"""``python -m pds_plugin.cli``: the ``pds-mesh`` command."""

import sys

from . import main

sys.exit(main())
