"""Policies behind one contract, greedy rollouts, and the loader that reads a rule file's kind once."""
