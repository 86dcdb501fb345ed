"""The classes of moves as arrays: exactly the tracker's list, state after state, on seeded towers."""

import numpy as np

from csql_sim.core.model.task_draws import tall_towers
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.state.move_classes import StateArrays, above_needed
from csql_sim.core.state.moves import Move, pick_action, put_action
from csql_sim.core.state.relation_tracker import RelationTracker
from csql_sim.infra.assets import builtin_rules_path


def walk(seed: int, trials: int, steps: int):
    """Trackers on seeded tall towers, each moved by random class moves: every hand-empty state on the way."""
    rng = np.random.default_rng(seed)
    for _ in range(trials):
        n = int(rng.integers(5, 50))
        goal = tall_towers(n, rng)
        tracker = RelationTracker(tall_towers(n, rng), goal)
        for _ in range(steps):
            state = tracker.state()
            if state == goal:
                break
            yield tracker
            x, d, _ = tracker.classes()[int(rng.integers(len(tracker.classes())))]
            tracker.apply(pick_action(state, x))
            tracker.apply(put_action(Move(x, d)))


def listed(arrays):
    xs, ds, bits = arrays
    return [(int(x), int(d), tuple(int(b) for b in row)) for x, d, row in zip(xs, ds, bits, strict=True)]


def test_the_arrays_are_the_list_of_classes_before_and_after_the_cover_is_found():
    for tracker in walk(4, 15, 40):
        assert listed(tracker.class_arrays(resolve=False)) == tracker.classes(resolve=False)
        tracker.resolve_cover()
        assert listed(tracker.class_arrays(resolve=False)) == tracker.classes(resolve=False)
        assert listed(tracker.class_arrays()) == tracker.classes()


def test_above_needed_by_doubling_is_the_walk_down_the_tower():
    for tracker in walk(6, 10, 30):
        arrays = StateArrays(tracker._sup_a, tracker._above_a, tracker._goal_a, tracker._goal_above_a,
                             tracker._placed_a, np.zeros(tracker.n, bool), None, None)  # stuck: not read
        got = above_needed(arrays, tracker._above_a < 0)
        assert got.tolist() == [tracker.above_needed(b) for b in range(tracker.n)]


def test_the_policy_picks_the_same_move_from_the_arrays_as_from_the_list():
    policy = load_policy(builtin_rules_path(), 40)
    for tracker in walk(9, 15, 40):
        for resolve in (False, True):
            assert policy._best_of_arrays(tracker.class_arrays(resolve)) == policy._best(tracker.classes(resolve))
