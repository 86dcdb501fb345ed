"""The jobs a user runs: evaluation, Figure 7, scaling, rendering, the benchmark, discovery on the arm.

Each job wires the layers below (learners, discovery, the simulator, the symbolic core);
the command line is a thin layer over these functions.
"""
