import numpy as np
import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import all_states
from csql_sim.sim.world.config import DEFAULT_CONFIG
from csql_sim.sim.world.layout import Placement, place_towers, start_layout, tower_slot
from csql_sim.sim.world.scene import Scene

SIZE = DEFAULT_CONFIG.physics.cube_size


@pytest.mark.parametrize("state", all_states(3), ids=lambda s: s.notation())
def test_layout_stacks_each_tower_in_its_slot(state):
    placed = {p.block: p for p in start_layout(state, DEFAULT_CONFIG)}
    assert sorted(placed) == list(range(3))
    towers = list(state.towers())
    slots = len(towers) + (state.held is not None)
    for k, tower in enumerate(towers):
        for level, block in enumerate(tower):
            p = placed[block]
            assert (p.x, p.y) == tower_slot(DEFAULT_CONFIG, k, slots) and p.yaw == 0.0
            assert p.z == pytest.approx(SIZE / 2 + level * SIZE, abs=1e-3)
    if state.held is not None:  # aside on the table, in the last slot
        p = placed[state.held]
        assert (p.x, p.y) == tower_slot(DEFAULT_CONFIG, slots - 1, slots)
        assert p.z == pytest.approx(SIZE / 2, abs=1e-3)


def test_slots_are_centred_and_spaced():
    ys = [tower_slot(DEFAULT_CONFIG, k, 3)[1] for k in range(3)]
    spacing = DEFAULT_CONFIG.layout.tower_spacing
    assert ys == pytest.approx([-spacing, 0.0, spacing])


def test_jitter_is_bounded_and_seeded():
    state = parse_config("CBA")
    a = start_layout(state, DEFAULT_CONFIG, np.random.default_rng(5), jitter=True)
    b = start_layout(state, DEFAULT_CONFIG, np.random.default_rng(5), jitter=True)
    plain = start_layout(state, DEFAULT_CONFIG)
    assert a == b and a != plain
    lay = DEFAULT_CONFIG.layout
    for p, q in zip(a, plain, strict=True):
        assert isinstance(p, Placement) and p.block == q.block and p.z == q.z
        assert abs(p.x - q.x) <= lay.jitter_xy and abs(p.y - q.y) <= lay.jitter_xy
        assert abs(p.yaw) <= lay.jitter_yaw


def test_place_towers_puts_the_cubes_there():
    state = parse_config("B,CA")
    with Scene(3) as scene:
        place_towers(scene, state)
        for p in start_layout(state, scene.config):
            assert scene.block_pose(p.block).position == pytest.approx((p.x, p.y, p.z))
