"""Gymnasium environments: the symbolic blocks world and the simulated arm, and their ids."""
