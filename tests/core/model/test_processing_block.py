from csql_sim.core.classifiers.classifier_list import ClassifierList
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.model.processing_block import ProcessingBlock
from csql_sim.core.model.world_model import WorldModel


def _block(clock):
    rules = r_classifiers(3)
    cl = ClassifierList(rules)
    return cl, ProcessingBlock(cl, WorldModel(rules, 3), lambda: {"q": 0.0, "born": clock[0]})


def test_post_matches_and_covers_once():
    clock = [5]
    cl, block = _block(clock)
    ms = block.post("S0111000ttt0000C")
    assert [c.action for c in ms.candidates] == ["A70000001000at00", "A80000001000bt00", "A90000001000ct00"]
    assert ms.actions == (6, 7, 8)  # pickup(A), pickup(B), pickup(C): codes 7, 8, 9
    assert ms.index_of(7) == 1
    assert len(cl.q_classifiers) == 3 and all(c.born == 5 for c in ms.candidates)
    clock[0] = 9
    assert block.post("S0111000ttt0000C") is ms  # memoized: no second cover
    assert len(cl.q_classifiers) == 3


def test_each_goal_gets_its_own_q_classifiers():
    cl, block = _block([0])
    a = block.post("S0111000ttt0000C")
    b = block.post("S0111000ttt00000")
    assert [c.action for c in a.candidates] == [c.action for c in b.candidates]
    assert not set(map(id, a.candidates)) & set(map(id, b.candidates))
    assert len(cl.q_classifiers) == 6
