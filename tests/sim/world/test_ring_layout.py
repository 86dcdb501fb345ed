"""The ring of thirty places past ten cubes: thirty spots, none overlapping, on the table, all within reach."""

import itertools
import math

import numpy as np

from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state import default_names
from csql_sim.sim.control.primitives import OFFSETS, housing_clear, shun_housing
from csql_sim.sim.world.config import MAX_ARM_BLOCKS, MAX_TOWER_HEIGHT, RING_CONFIG, WIDE_CONFIG, config_for
from csql_sim.sim.world.layout import arc_place, putdown_spots, start_layout
from csql_sim.sim.world.robot import EE_LINK, KINEMATIC_BODY, LOWER, UPPER, Panda
from csql_sim.sim.world.scene import Scene
from csql_sim.sim.world.tower_height import tall_bases

SIZE = RING_CONFIG.physics.cube_size


def test_thirty_places_none_overlapping_all_on_the_table():
    assert config_for(10) is WIDE_CONFIG and config_for(11) is config_for(30) is RING_CONFIG
    spots = putdown_spots(RING_CONFIG)
    assert len(spots) == len(set(spots)) == MAX_ARM_BLOCKS == 30
    gaps = [math.dist(a, b) for a, b in itertools.combinations(spots, 2)]
    assert min(gaps) > SIZE * math.sqrt(2) + 0.02  # two cubes at any yaw, 2 cm apart at least
    assert min(gaps) >= RING_CONFIG.layout.free_clearance  # a cube on one place leaves the next one free
    (cx, cy, _), half = RING_CONFIG.physics.table_centre, RING_CONFIG.physics.table_half_extents
    assert all(abs(x - cx) < half[0] - 0.1 and abs(y - cy) < half[1] - 0.1 for x, y in spots)
    placed = start_layout(parse_config(", ".join(default_names(30))), RING_CONFIG)
    assert sorted((round(p.x, 9), round(p.y, 9)) for p in placed) == sorted(
        (round(x, 9), round(y, 9)) for x, y in spots)  # every cube on the table at once: one place each
    three = start_layout(parse_config("ABCDEFGHIJ,KLMNOPQRST,UVWXYZ"), RING_CONFIG)
    spots3 = sorted({(round(p.x, 9), round(p.y, 9)) for p in three}, key=lambda s: math.atan2(s[1], s[0]))
    assert len(spots3) == 3 and all(abs(math.dist(a, b) - 2 * 0.09) < 0.01  # on every other place
                                    for a, b in itertools.pairwise(spots3))
    assert all(abs(math.atan2(y, x)) < 0.5 for x, y in spots3)  # in the middle of the ring


def test_every_place_is_within_reach_from_the_table_to_above_the_tallest_tower():
    carry = min(MAX_TOWER_HEIGHT * SIZE + SIZE / 2 + OFFSETS.carry_clearance, RING_CONFIG.control.carry_ceiling)
    heights = (SIZE / 2, SIZE / 2 + (MAX_TOWER_HEIGHT - 1) * SIZE, carry)  # a table cube, the top cube, the carry
    assert carry >= MAX_TOWER_HEIGHT * SIZE + SIZE / 2 + 0.03  # the carried cube clears the tallest tower
    with Scene(2, RING_CONFIG) as scene:
        panda, model = Panda(scene), scene.kinematics
        assert model is not None
        for i in range(RING_CONFIG.layout.arc_positions):
            x, y, yaw = arc_place(RING_CONFIG, i)
            for z in heights:
                hand = panda.wrist_fit(x, y)(yaw + math.pi / 2)  # the fingers close along the ring's radius
                q = panda.ik((x, y, z), hand)
                assert all(lo - 1e-6 <= v <= hi + 1e-6 for v, lo, hi in zip(q, LOWER, UPPER, strict=True))
                for j, v in enumerate(q):
                    model.reset_joint(KINEMATIC_BODY, j, v)
                reached = model.link_state(KINEMATIC_BODY, EE_LINK)[0]
                assert np.linalg.norm(np.subtract(reached, (x, y, z))) < 0.003, (i, z)


def test_putdowns_shun_places_where_a_tall_neighbour_stands_in_the_housings_way():
    (x0, y0), (x1, y1), (x2, y2) = putdown_spots(RING_CONFIG)[10:13]
    tall = [(x1, y1, SIZE / 2 + k * SIZE) for k in range(6)]  # a tower of six on place 11
    assert not housing_clear(tall, SIZE, x0, y0)  # its clockwise neighbour: the housing passes over place 11
    assert housing_clear(tall, SIZE, x2, y2)  # its anticlockwise neighbour: the housing is on the other side
    assert housing_clear(tall[:4], SIZE, x0, y0)  # a tower of four is below the housing


def test_putdowns_keep_the_places_beside_a_tall_goal_towers_bottom_clear():
    spots = putdown_spots(RING_CONFIG)
    base = [(*spots[11], SIZE / 2)]  # one cube on place 11, the bottom of a tall goal tower
    kept = shun_housing(spots, base, SIZE, base=False, bases=base)
    assert spots[10] not in kept and len(kept) == len(spots) - 1  # going down at 10, the housing passes 11
    free = [(*spots[k], SIZE / 2) for k in (5, 20)]  # two cubes on the table; the bottom is held
    kept = shun_housing(spots, free, SIZE, base=True, bases=[])
    assert spots[6] not in kept and spots[21] not in kept and len(kept) == len(spots) - 2  # not beside them
    assert shun_housing(spots, free, SIZE, base=False, bases=[]) == spots  # an ordinary cube: anywhere
    assert tall_bases(parse_config("ABCDE,FG,HIJKL")) == {0, 7} and tall_bases(parse_config("ABCD,E")) == set()
    crowded = [(*spots[k], SIZE / 2) for k in range(1, 30)]  # only place 2 offered, beside the cube on 1: the fallback
    assert shun_housing(spots[2:3], crowded[:1], SIZE, base=True, bases=[]) == spots[2:3]  # beside the cube on 1
    tall = [(*spots[k], SIZE / 2 + h * SIZE) for k in range(0, 30, 2) for h in range(6)]  # towers of six
    fallback = shun_housing(spots[1::2], tall, SIZE, base=True, bases=[])
    assert fallback == [s for s in spots[1::2] if housing_clear(tall, SIZE, *s)] and 0 < len(fallback) < 15
