"""The symbolic core: the blocks world, the paper's messages and classifiers, the world model.

World, notation and messages; R- and Q-classifiers and the one classifier list; the world
model and its transition table; the processing block; symbolic search (BFS distances,
greedy rollouts, all-pairs checks); policies; rule files. Never imports pybullet.
"""
