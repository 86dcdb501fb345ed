"""The ground Q-classifiers of LQ-CS: one-move backups through the model, made on demand."""

from csql_sim.core.state.moves import moves, pick_action
from csql_sim.core.state.notation import parse_config
from csql_sim.learners.lifted.given import GivenAtoms, MisplacedCosts
from csql_sim.learners.lifted.ground import GroundValues, RewardCosts


def test_a_backup_counts_moves_plus_early_per_block_left_misplaced():
    ground = GroundValues(GivenAtoms().relations, MisplacedCosts(0.25))
    state, target = parse_config("A,B,C"), parse_config("ABC")
    i = ground.of(state, target)
    assert ground.of(state, target) == i and ground.low[i] == 2  # B and C are misplaced
    q = ground.backup(i)
    options = ground.moves_of(i)[0]
    assert options == moves(state) and len(q) == len(options) == len(ground.successors(i))
    # B onto A leaves C misplaced: 1 + 0.25 x 1 + 1 (the successor's lower bound, excess 0 so far)
    assert q[options.index(next(m for m in options if (m.block, m.onto) == (1, 0)))] == 2.25
    assert min(q) == 2.25 and ground.excess[i] == 0.25
    # once the successor is known to be one move from the target, the bound holds exactly
    j = ground.successors(i)[options.index(next(m for m in options if (m.block, m.onto) == (1, 0)))]
    assert min(ground.backup(j)) == 1.0 and ground.excess[j] == 0.0


def test_reward_only_values_settle_to_the_optimal_plan_length_in_moves():
    """-1 per action, 0 at the goal: value iteration from 0 gives every state its BFS distance (actions / 2)."""
    from csql_sim.core.model.search import distance
    from csql_sim.core.state.world import all_states, successor

    start_goal = parse_config("AB,CD")
    held_goal = successor(start_goal, pick_action(start_goal, 1))  # ends holding B
    for goal in (start_goal, held_goal):
        ground = GroundValues(lambda s, t: ((), None), RewardCosts(2))
        states = [s for s in all_states(4) if s.held is None]
        index = [ground.of(s, goal) for s in states]
        for _ in range(20):
            for i in index:
                if not ground.final[i]:
                    ground.backup(i)
        for s, i in zip(states, index, strict=True):
            assert ground.low[i] + ground.excess[i] == distance(s, goal) / 2, s.notation()
