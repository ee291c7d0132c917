"""``python -m exudyn_wheelrail.cli``: the command line, as ``python -m exudyn_wheelrail``."""
import sys

from . import main

sys.exit(main())
