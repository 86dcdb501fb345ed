"""Measuring, never planning: the exact optimum. Policies and learners never import it."""
