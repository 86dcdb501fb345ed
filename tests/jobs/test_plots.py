"""The figures' small promises: titles that match what is drawn, whole-number ticks on counts."""

import numpy as np

from csql_sim.jobs.plots import _integer_ticks, new_figure
from csql_sim.jobs.scaling import ScalingRow, figure


def _row(method, blocks, trials):
    return ScalingRow(method, blocks, trials, 100, 0.1, 10, 10)


def test_scaling_title_explains_hollow_markers_only_when_some_are_drawn():
    reached = figure([_row("cs-ql", 2, 50), _row("cs-ql", 3, 500)], 1000)
    assert "hollow" not in reached.axes[0].get_title()
    capped = figure([_row("cs-ql", 2, 50), _row("lt-ql", 3, None)], 1000)
    assert "hollow: not reached within 1000 trials" in capped.axes[0].get_title()


def test_count_axes_have_whole_number_ticks():
    ax = new_figure(4, 3).subplots()
    ax.bar([1, 2], [1, 2])
    _integer_ticks(ax)
    ax.figure.canvas.draw()
    for ticks in (ax.get_xticks(), ax.get_yticks()):
        assert np.allclose(ticks, np.round(ticks))
