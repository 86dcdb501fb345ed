"""Pick and place on the ring of 11..30 cubes (``RING_CONFIG``): a grasp that ends once the fingers
stop closing, a release that opens just wide enough, and moves that hand over to the next one
without stopping; against the ring's earlier control, which waits (``WAITING_CONTROL``)."""

import dataclasses
import math

import numpy as np
import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import Action, ActionKind
from csql_sim.sim.control.physical import PhysicalWorld
from csql_sim.sim.control.primitives import OFFSETS, Place
from csql_sim.sim.perception.poses import BlockObs
from csql_sim.sim.world.config import RING_CONFIG, WAITING_CONTROL

SIZE = RING_CONFIG.physics.cube_size
RING = RING_CONFIG.control
WAITING_CONFIG = dataclasses.replace(RING_CONFIG, control=WAITING_CONTROL)
START = parse_config("A,B,CDEFGHIJ,K,L")  # a tower of eight (C..J) in the middle of the ring, four single cubes
TOWER, SINGLES = range(2, 10), (0, 1, 10, 11)




def angle(p) -> float:
    return math.atan2(p[1], p[0])


def far_single(world: PhysicalWorld) -> int:
    """A single cube two places or more from the tower, with the tower between it and the hand's start angle."""
    obs = world.observe()
    tower, hand = angle(obs.blocks[TOWER[0]].position), angle(world.panda.ee_position())
    at = {i: angle(obs.blocks[i].position) for i in SINGLES}
    singles = [i for i in SINGLES
               if abs(at[i] - tower) > 0.35 and min(hand, at[i]) - 0.2 <= tower <= max(hand, at[i]) + 0.2]
    assert singles, "the layout puts a single cube beyond the tower"
    return singles[0]


def pick_and_put_down(config) -> dict:
    with PhysicalWorld(12, 0, "pose", config) as world:
        world.build(START)
        block = far_single(world)
        closing = {}
        close = world.panda.close

        def timed_close(body):
            before = world.scene.steps
            ok = close(body)
            closing["steps"] = world.scene.steps - before
            return ok

        world.panda.close = timed_close
        picked = world.execute(Action(ActionKind.PICKUP, block))
        held = world.observe()
        hand = world.panda.ee_position()
        put = world.execute(Action(ActionKind.PUTDOWN, block))
        return {"picked": picked, "put": put, "hand_z": float(hand[2]), "cube_z": held.blocks[block].position[2],
                "tower_top": held.blocks[TOWER[-1]].position[2] + SIZE / 2, "width": world.panda.finger_width(),
                "state": world.perceive().state, "close": closing["steps"]}


@pytest.fixture(scope="module")
def ring() -> dict:
    return pick_and_put_down(RING_CONFIG)


@pytest.fixture(scope="module")
def waiting() -> dict:
    return pick_and_put_down(WAITING_CONFIG)


def test_a_pick_carries_the_cube_out_of_the_cameras_way_and_a_place_puts_it_back(ring, waiting):
    assert ring["picked"].ok and waiting["picked"].ok and ring["put"].ok and waiting["put"].ok
    for run in (ring, waiting):  # the cube hangs in the hand, its grasp point just above its centre
        assert abs(run["hand_z"] - run["cube_z"] - OFFSETS.grasp_above_centre) < 0.01
        assert run["hand_z"] > run["tower_top"] + SIZE / 2  # carried above the tower of eight on its way
        assert run["state"] == START  # put down again: the same state, perceived


def test_the_grasp_ends_once_the_fingers_stop_closing_and_still_holds(ring, waiting):
    # the fingers go on squeezing the cube by 0.1 mm at a time: waiting for less than that takes the whole cap
    assert ring["close"] < RING.grip_steps <= waiting["close"]
    assert ring["picked"].steps < waiting["picked"].steps


def test_a_release_opens_just_wider_than_the_cube(ring, waiting):
    assert abs(ring["width"] - (SIZE + RING.release_opening)) < 0.006
    assert waiting["width"] > 2 * RING.finger_open - 0.006  # fully open without it


def test_a_move_that_another_continues_ends_near_its_goal_without_waiting_to_stop():
    steps, ends = {}, {}
    for rest in (True, False):
        with PhysicalWorld(12, 0, "pose", RING_CONFIG) as world:
            world.build(START)
            panda = world.panda
            goal = panda.ee_position() + np.array([0.0, 0.0, -0.2])
            before = world.scene.steps
            assert panda.move_to(tuple(goal), panda.yaw, RING.move_speed, 300, rest=rest) == "reached"
            steps[rest] = world.scene.steps - before
            ends[rest] = float(np.linalg.norm(panda.ee_position() - goal))
    assert ends[True] < RING.reach_tolerance and ends[False] < RING.blend_tolerance
    assert steps[False] < steps[True]


def unread(obs, block):
    """``obs`` as camera perception gives it when no view reads ``block`` (held: known only by elimination)."""
    blocks = list(obs.blocks)
    blocks[block] = BlockObs((0.0, 0.0, -1.0), None, 0.0, visible=False)
    return dataclasses.replace(obs, blocks=tuple(blocks))


def test_a_cube_unread_in_the_hand_is_put_down_and_stacked_where_it_should_be():
    with PhysicalWorld(12, 0, "pose", RING_CONFIG) as world:
        world.build(parse_config("A,B,CDEFGHIJ,K+L"))
        down = Place(11, None)(world.scene, world.panda, unread(world.observe(), 11), world.rng)
        assert down.ok and world.perceive().state == parse_config("A,B,CDEFGHIJ,K,L")
        on_ring = [math.hypot(*world.scene.block_pose(i).position[:2]) for i in (0, 1, 10, 11)]
        assert max(on_ring) - min(on_ring) < 0.02  # on the ring's places, not by the arm's base
        assert world.execute(Action(ActionKind.PICKUP, 11)).ok
        onto = Place(11, 10)(world.scene, world.panda, unread(world.observe(), 11), world.rng)
        assert onto.ok and world.perceive().state == parse_config("A,B,CDEFGHIJ,KL")
