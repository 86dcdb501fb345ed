"""The blocks world's states and their views.

The world, notations, the paper's messages, goal and move relations, state counting.
"""
