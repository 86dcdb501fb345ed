"""The cubes' legend: object name -> colour, in cube order."""

import pytest

from csql_sim.sim.world.config import COLOUR_NAMES, COLOURS
from csql_sim.sim.world.legend import cube_legend, legend_line, legend_names


def test_letters_by_default_and_names_in_cube_order():
    assert cube_legend(3) == {"A": "red", "B": "green", "C": "blue"}
    assert list(cube_legend(10).values()) == list(COLOUR_NAMES) and len(COLOUR_NAMES) == len(COLOURS)
    assert cube_legend(2, ("x-ray", "Ruby")) == {"x-ray": "red", "Ruby": "green"}
    assert legend_line(2, ("b2", "b10")) == "legend: b2 = red, b10 = green"


def test_a_name_per_cube():
    assert legend_names(2) == ("A", "B")
    with pytest.raises(ValueError, match="3 names for 2 cubes"):
        legend_names(2, ("a", "b", "c"))
