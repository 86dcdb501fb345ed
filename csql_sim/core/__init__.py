"""The symbolic core, by concept; never imports pybullet.

* :mod:`~csql_sim.core.state`: the blocks world, notations, the paper's messages, relations.
* :mod:`~csql_sim.core.classifiers`: R- and Q-classifiers, the classifier list, lifted rules.
* :mod:`~csql_sim.core.model`: the world model, the processing block, search, goals, pairs.
* :mod:`~csql_sim.core.files`: rule files, PDDL in and out, plan files.
* :mod:`~csql_sim.core.policies`: every policy behind one contract, rollouts, the loader.
* :mod:`~csql_sim.core.measure`: the exact optimum; policies and learners never import it.
"""
