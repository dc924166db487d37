"""``python -m mrexplore`` runs the command-line interface."""

import sys

from mrexplore.cli import main

sys.exit(main())
