"""Bad constructor and reset arguments of both environments fail with a CsqlError naming the argument.

Before the checks, ``width=0`` gave empty images, ``width=height=100000`` aborted the
interpreter and ``width=-5, height=0`` crashed it in ``render()``; ``max_steps=-1`` was
taken and ``reset(options=[...])`` raised an AttributeError. Nothing here starts physics:
the checks come before any scene is built.
"""

import numpy as np
import pytest

from csql_sim.envs.physical import MAX_IMAGE_SIDE, MIN_IMAGE_SIDE, PhysicalBlocksEnv
from csql_sim.envs.symbolic import BlocksWorldEnv
from csql_sim.infra.errors import CsqlError

ENVS = [BlocksWorldEnv, PhysicalBlocksEnv]


@pytest.mark.parametrize("size", [{"width": 0}, {"height": 0}, {"width": -5, "height": 0},
                                  {"width": 100000, "height": 100000}, {"width": MIN_IMAGE_SIDE - 1},
                                  {"height": MAX_IMAGE_SIDE + 1}, {"width": 64.0}, {"height": "480"},
                                  {"width": True}, {"width": None}])
def test_image_size_out_of_range_or_not_an_integer_is_refused(size):
    with pytest.raises(CsqlError, match=next(iter(size))):
        PhysicalBlocksEnv(render_mode="rgb_array", **size)


def test_image_sizes_at_the_documented_bounds_are_taken():
    env = PhysicalBlocksEnv(render_mode="rgb_array", width=MIN_IMAGE_SIDE, height=np.int64(MAX_IMAGE_SIDE))
    assert (env.width, env.height) == (MIN_IMAGE_SIDE, MAX_IMAGE_SIDE) and type(env.height) is int


@pytest.mark.parametrize("env_class", ENVS)
@pytest.mark.parametrize("max_steps", [-1, 0, 2.5, "10", True])
def test_max_steps_must_be_none_or_a_positive_integer(env_class, max_steps):
    with pytest.raises(CsqlError, match="max_steps"):
        env_class(max_steps=max_steps)


@pytest.mark.parametrize("env_class", ENVS)
def test_valid_max_steps_are_taken(env_class):
    assert env_class(max_steps=None).max_steps is None
    assert env_class(max_steps=np.int32(5)).max_steps == 5


@pytest.mark.parametrize("env_class", ENVS)
@pytest.mark.parametrize("options", [["start"], "start=CBA", ("CBA", "BAC"), 3])
def test_reset_options_must_be_a_dict(env_class, options):
    env = env_class()
    with pytest.raises(CsqlError, match="options"):
        env.reset(seed=0, options=options)
    assert getattr(env, "physical", None) is None  # nothing was built


def test_valid_arguments_still_work():
    env = BlocksWorldEnv(max_steps=1)
    _obs, info = env.reset(seed=0, options={"start": "CBA", "goal": "BAC"})
    illegal = int(np.flatnonzero(info["action_mask"] == 0)[0])
    assert env.step(illegal)[3] is True
    assert BlocksWorldEnv().reset(seed=0, options={})[0] == BlocksWorldEnv().reset(seed=0, options=None)[0]
