"""csql-sim: classifier-system Q-learning on the blocks world, executed on a simulated arm."""

__version__ = "0.1.0"
