"""``python -m csql_sim`` runs the command line."""

from csql_sim.cli import console

console()
