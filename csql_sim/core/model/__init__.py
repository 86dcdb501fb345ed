"""The world model.

The transition table, the processing block, search, goals as sets of states, the test task, pair sampling.
"""
