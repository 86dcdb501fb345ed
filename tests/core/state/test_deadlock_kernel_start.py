"""The compiled deadlock kernels, started in a fresh process (the BLAS probe skipped), count what the reference counts.

Whether numba then imports SciPy's linalg is numba's own business (its internals may change);
the test asserts only the kernels' answers and that the probe's placeholder is gone.
"""

import json
import subprocess
import sys

CHILD = r"""
import json, sys
import numpy as np
from csql_sim.core.state.deadlock_kernel import deadlocked
from csql_sim.core.state.goal_relations import deadlocked as reference, well_placed
from csql_sim.core.state.notation import parse_config
state, goal = parse_config("BA,C"), parse_config("CBA")  # B must move first, A is on it
n = state.n
above = np.full(n, -1, np.int64)
for b, s in enumerate(state.support):
    if s >= 0:
        above[s] = b
goal_a = np.array(goal.support, np.int64)
placed = np.array(well_placed(state, goal), np.bool_)
stuck = np.zeros(n, np.bool_)
count = deadlocked(above, goal_a, placed, stuck)
print(json.dumps({"count": int(count), "stuck": np.flatnonzero(stuck).tolist(),
                  "reference": sorted(reference(state, goal)),
                  "placeholder": sys.modules.get("scipy.linalg.cython_blas", 0) is None}))
"""


def test_a_fresh_process_runs_the_kernels_and_leaves_no_placeholder_module():
    done = subprocess.run([sys.executable, "-c", CHILD], check=True, capture_output=True, text=True)
    got = json.loads(done.stdout.strip().splitlines()[-1])
    assert got["stuck"] == got["reference"] and got["count"] == len(got["reference"]) > 0
    assert got["placeholder"] is False
