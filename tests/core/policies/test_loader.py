"""load_policy reads a rule file once and dispatches through the registry of kinds, one loader each."""

import builtins
import os
from pathlib import Path

import pytest

import csql_sim.core.policies.loader as loader
from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.files import kinds
from csql_sim.core.files.rulebase import RuleBase, save
from csql_sim.core.model.search import BfsPolicy
from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.policies.lifted_classifier import LiftedQClassifier
from csql_sim.core.policies.lifted_policy import LiftedPolicy, dumps_lifted_policy
from csql_sim.core.policies.sharded_policy import ShardedPolicy
from csql_sim.core.state.goal_message import GoalForm
from csql_sim.core.state.message import action_messages, format_state_message
from csql_sim.core.state.notation import parse_state_arg
from csql_sim.core.state.world import BlocksWorld
from csql_sim.infra.errors import CsqlError

SHIPPED = Path(__file__).resolve().parents[3] / "assets" / "rules" / "lifted.json"


def _pair(n: int = 3) -> tuple:
    """Every block on the table -> B on A; BFS's first step (pickup(B)) is what each file says."""
    letters = "ABCDEF"[:n]
    start, goal = parse_state_arg(",".join(letters), n), parse_state_arg(",".join(["AB", *letters[2:]]), n)
    return start, goal, BfsPolicy().act(start, goal)


def _ground(n: int = 3) -> RuleBase:
    """One index-form Q-classifier: in the pair's start towards its goal, BFS's first step."""
    world = BlocksWorld.of(n)
    start, goal, step = _pair(n)
    message = action_messages(n)[world.action_index(step)]
    return RuleBase(n, [QClassifier(format_state_message(start, world.state_index(goal)), message)])


def _goal_form() -> RuleBase:
    """One goal-form Q-classifier that matches every pair: BFS's first step of the pair."""
    message = action_messages(3)[BlocksWorld.of(3).action_index(_pair()[2])]
    return RuleBase(3, [QClassifier("S" + "#" * 14 + "G" + "#" * 25, message)], GoalForm(3).meta())


def _sharded(tmp_path: Path) -> Path:
    from csql_sim.learners.paper.params import defaults_for_blocks
    from csql_sim.learners.training.shards import ShardRun, train_sharded

    out = tmp_path / "sharded"
    train_sharded(ShardRun(out, 3, defaults_for_blocks("cs-ql", 3), 0, 2000, 2))
    return out


def _write(kind: str, tmp_path: Path) -> Path:
    """A rule file (or directory) of ``kind``."""
    if kind == kinds.SHARDED:
        return _sharded(tmp_path)
    if kind == kinds.LIFTED:
        path = tmp_path / "lifted.json"
        path.write_bytes(SHIPPED.read_bytes())
        return path
    suffix = ".npz" if "npz" in kind else ".yaml"
    rulebase = _goal_form() if kind in (kinds.GOAL_YAML, kinds.GOAL_NPZ) else _ground()
    return save(tmp_path / f"rules{suffix}", rulebase)


EXPECTED = {kinds.GROUND_YAML: GreedyTable, kinds.GROUND_NPZ: GreedyTable, kinds.GOAL_YAML: GreedyTable,
            kinds.GOAL_NPZ: GreedyTable, kinds.SHARDED: ShardedPolicy, kinds.LIFTED: LiftedPolicy}


def _count_opens(monkeypatch) -> list[str]:
    """Record every file opened from now on (os.open and open), by its path."""
    opened: list[str] = []
    os_open, open_ = os.open, builtins.open

    def counting_os_open(path, *a, **k):
        opened.append(os.path.realpath(path))
        return os_open(path, *a, **k)

    def counting_open(file, *a, **k):
        if isinstance(file, (str, os.PathLike)):
            opened.append(os.path.realpath(file))
        return open_(file, *a, **k)

    monkeypatch.setattr(os, "open", counting_os_open)
    monkeypatch.setattr(builtins, "open", counting_open)
    return opened


@pytest.mark.parametrize("kind", kinds.KINDS)
def test_each_kind_is_read_once_and_dispatched_through_the_registry(kind, tmp_path, monkeypatch):
    path = _write(kind, tmp_path)
    called: list[str] = []
    spies = {k: (lambda f, *a, _k=k, _load=load: called.append(_k) or _load(f, *a)) for k, load in
             loader.LOADERS.items()}
    monkeypatch.setattr(loader, "LOADERS", spies)
    opened = _count_opens(monkeypatch)
    policy = loader.load_policy(path, None if kind == kinds.LIFTED else 3)
    monkeypatch.undo()
    assert called == [kind]  # one loader, the kind's own
    assert type(policy) is EXPECTED[kind] and isinstance(policy, Policy)
    inside = [p for p in opened if p == os.path.realpath(path) or p.startswith(os.path.realpath(path) + os.sep)]
    assert len(inside) == 1  # the file (a sharded base: its manifest) opened once, read once
    if kind == kinds.SHARDED:
        assert inside == [os.path.realpath(path / "manifest.json")]
    start, goal, step = _pair()
    assert step.name() == "pickup(B)" and policy.act(start, goal) == step


def test_every_kind_has_a_loader():
    assert set(loader.LOADERS) == set(kinds.KINDS)


def test_without_a_file_the_policy_is_bfs_and_past_six_blocks_refused():
    assert isinstance(loader.load_policy(None), BfsPolicy)
    with pytest.raises(CsqlError, match="BFS enumerates every state .* --planner gn1"):
        loader.load_policy(None, 7)


def test_a_ground_file_past_six_blocks_is_refused_with_the_hint_a_lifted_file_without(tmp_path):
    ground = save(tmp_path / "r3.yaml", _ground())
    with pytest.raises(CsqlError, match=r"is for 3 blocks, not 8; past six blocks plan with lifted rules"):
        loader.load_policy(ground, 8)
    lifted = tmp_path / "big.json"
    lifted.write_text(dumps_lifted_policy([LiftedQClassifier("1########", "table")], {"pad": "x" * (1 << 20)}))
    with pytest.raises(CsqlError, match="limit for a lifted Q-classifier file$"):
        loader.load_policy(lifted, 8)


def test_an_npz_for_other_blocks_is_refused_in_one_line(tmp_path):
    path = save(tmp_path / "r4.npz", _ground(4))
    with pytest.raises(CsqlError, match=r"^rule base '.*r4.npz' is for 4 blocks, not 3$"):
        loader.load_policy(path, 3)
    goal = save(tmp_path / "g.npz", _goal_form())
    with pytest.raises(CsqlError, match=r"^rule file '.*g.npz' is for 3 blocks, not 4$"):
        loader.load_policy(goal, 4)
