"""Package data: the paper's rule asset (``rules/blocks3.yaml``), installed as ``csql_sim.assets``."""
