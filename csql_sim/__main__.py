"""``python -m csql_sim`` runs the command line."""

import sys

from csql_sim.cli import main

sys.exit(main())
