"""The feature grammar: description-logic concepts and roles over a domain's predicates.

Following Bonet, Francès and Geffner (AAAI 2019) and ``dlplan``, a **concept** denotes a set
of objects in a state and a **role** a set of pairs, both built from the predicates of the
domain (:class:`~csql_sim.core.features.formulation.Formulation`) and their goal versions:

==================  ============  =====================================================
written             notation      denotes
==================  ============  =====================================================
``top``             ⊤             every object
``p``               p             the objects of unary predicate ``p``
``p[0]``, ``p[1]``  p[0], p[1]    the first / second arguments of binary predicate ``p``
``{c}``             {c}           the constant ``c`` (a nominal: ``{table}``)
``not(C)``          ¬C            the objects not in C
``and(C,D)``        C ⊓ D         the objects in both
``some(R,C)``       ∃R.C          the x with some y in C and R(x, y)
``all(R,C)``        ∀R.C          the x whose every R-successor y is in C
``eq(R,S)``         (R = S)       the x whose R-successors are its S-successors (role-value map)
``self(R)``         ∃R.Self       the x with R(x, x): on a cycle, when R is a closure
``r``               r             the pairs of binary predicate ``r``
``inv(R)``          R⁻¹           R reversed
``plus(R)``         R⁺            the transitive closure of R
``star(R)``         R*            the reflexive-transitive closure of R
``comp(R,S)``       R ∘ S         the (x, z) with some y, R(x, y) and S(y, z) (composition)
``or(R,S)``         R ⊔ S         the pairs of either (role union)
``restrict(R,C)``   R|C           the (x, y) of R with y in C
==================  ============  =====================================================

Composition, union and restriction make orderings between blocks expressible as roles, and
their closures and cycles as concepts. The waits of the deadlock graph, for instance: b must
wait for the block on it (``inv(on)``) and for the block on its goal support
(``comp(on_g,inv(on))``), so ``self(plus(or(inv(on),comp(on_g,inv(on)))))`` (complexity 9)
holds the blocks on a cycle of those waits. It is not yet the deadlock: the graph's edges run
between misplaced blocks only (``some(star(on),not(eq(on,on_g)))``, complexity 7), and
restricting both ends to them takes the expression far past the bound; the well-placed blocks
themselves are ``all(star(on),eq(on,on_g))`` (complexity 6).

**Counts** are the numerical features: ``|C|`` of a concept and ``|R|`` of a role, in each
state (:meth:`~csql_sim.core.features.denotation.Denotations.count`); a count has the
complexity of its node. The **complexity** of an expression counts each constructor and
each primitive as 1 (``all(star(on),eq(on,on_g))`` has 6); the generator enumerates every
expression up to the bound K and no further, so what it can say is explicit. Nodes are
immutable and hashable; :func:`parse` reads the written form back, and :meth:`Node.words`
gives the notation.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from csql_sim.infra.errors import CsqlError

CONCEPT_OPS = ("top", "pred", "proj", "nom", "not", "and", "some", "all", "eq", "self")
ROLE_OPS = ("role", "inv", "plus", "star", "comp", "or", "restrict")
MAX_LENGTH = 1000
"""The longest written expression read (characters): generated features have complexity up to about 10."""
MAX_DEPTH = 32
"""The deepest nesting of constructors read: deeper input is refused before any recursion."""
_TOKEN = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_\-]*|\[[01]\]|\{[A-Za-z_][A-Za-z0-9_\-]*\}|[(),])")


class GrammarError(CsqlError):
    """An expression of the feature grammar that cannot be read."""


@dataclass(frozen=True)
class Node:
    """A concept or role: its constructor ``op``, its arguments (nodes, or a name and position)."""

    op: str
    args: tuple = ()

    @property
    def is_role(self) -> bool:
        """Whether the node is a role (else a concept)."""
        return self.op in ROLE_OPS

    @property
    def complexity(self) -> int:
        """Each constructor and each primitive counts 1."""
        return 1 + sum(a.complexity for a in self.args if isinstance(a, Node))

    def uses(self) -> set[tuple[str, int | None]]:
        """The predicates the node reads, with their arities, and its constants (arity None)."""
        arity = {"pred": 1, "role": 2, "proj": 2, "nom": None}
        if self.op in arity:
            return {(self.args[0], arity[self.op])}
        return set().union(*(a.uses() for a in self.args if isinstance(a, Node)))

    def text(self) -> str:
        """The written form, read back by :func:`parse`."""
        op, a = self.op, self.args
        if op == "top":
            return "top"
        if op in ("pred", "role"):
            return a[0]
        if op == "proj":
            return f"{a[0]}[{a[1]}]"
        if op == "nom":
            return "{" + a[0] + "}"
        return f"{op}({','.join(x.text() for x in a)})"

    def words(self) -> str:
        """The description-logic notation (``∀on*.(on = on_g)``)."""
        op, a = self.op, self.args
        simple = {"top": "⊤", "pred": a[0] if a else "", "role": a[0] if a else ""}
        if op in simple:
            return simple[op]
        if op == "proj":
            return f"{a[0]}[{a[1]}]"
        if op == "nom":
            return "{" + a[0] + "}"
        inner = [x.words() for x in a]
        wrap = [w if _atomic(w) else f"({w})" for w in inner]
        forms = {"not": lambda: f"¬{wrap[0]}", "and": lambda: f"{wrap[0]} ⊓ {wrap[1]}",
                 "some": lambda: f"∃{wrap[0]}.{wrap[1]}", "all": lambda: f"∀{wrap[0]}.{wrap[1]}",
                 "eq": lambda: f"({inner[0]} = {inner[1]})", "inv": lambda: f"{wrap[0]}⁻¹",
                 "plus": lambda: f"{wrap[0]}⁺", "star": lambda: f"{wrap[0]}*",
                 "self": lambda: f"∃{wrap[0]}.Self", "comp": lambda: f"{wrap[0]} ∘ {wrap[1]}",
                 "or": lambda: f"{wrap[0]} ⊔ {wrap[1]}", "restrict": lambda: f"{wrap[0]}|{wrap[1]}"}
        return forms[op]()


TOP = Node("top")


def _atomic(words: str) -> bool:
    """Whether written notation needs no parentheses as an argument: no infix operator at its top."""
    depth = 0
    for ch in words:
        depth += ch in "({"
        depth -= ch in ")}"
        if depth == 0 and ch in " ⊓=|":
            return False
    return True


def pred(name: str) -> Node:
    """A unary predicate as a concept."""
    return Node("pred", (name,))


def role(name: str) -> Node:
    """A binary predicate as a role."""
    return Node("role", (name,))


def parse(text: str, is_role: bool = False) -> Node:
    """The node of a written concept (a role with ``is_role``); GrammarError if it is not one.

    A name's arity is the domain's business: ``some(clear,on)`` reads, and evaluating it
    names the missing predicate (:class:`~csql_sim.core.features.denotation.Denotations`).
    """
    if len(text) > MAX_LENGTH:
        raise GrammarError(f"feature {text[:60]!r}...: longer than {MAX_LENGTH} characters")
    tokens = _TOKEN.findall(text)
    _check_depth(tokens, text)
    if "".join(tokens) != re.sub(r"\s+", "", text) or not tokens:
        raise GrammarError(f"feature {text[:80]!r}: not an expression of the feature grammar")
    node, at = _parse_at(tokens, 0, text, "r" if is_role else "c")
    if at != len(tokens):
        raise GrammarError(f"feature {text[:80]!r}: unexpected {tokens[at]!r}")
    return node


_ARITY = {"not": ("c",), "and": ("c", "c"), "some": ("r", "c"), "all": ("r", "c"), "eq": ("r", "r"),
          "self": ("r",), "inv": ("r",), "plus": ("r",), "star": ("r",), "comp": ("r", "r"), "or": ("r", "r"),
          "restrict": ("r", "c")}


def _check_depth(tokens: list[str], text: str) -> None:
    """Refuse nesting deeper than :data:`MAX_DEPTH` (counted without recursion, before parsing)."""
    depth = 0
    for token in tokens:
        depth += (token == "(") - (token == ")")
        if depth > MAX_DEPTH:
            raise GrammarError(f"feature {text[:60]!r}...: nested deeper than {MAX_DEPTH} levels")


def _parse_at(tokens: list[str], at: int, text: str, want: str | None = None) -> tuple[Node, int]:
    if at >= len(tokens):
        raise GrammarError(f"feature {text[:80]!r}: ends early")
    head = tokens[at]
    if head in _ARITY and at + 1 < len(tokens) and tokens[at + 1] == "(":
        args, at = [], at + 2
        for i, kind in enumerate(_ARITY[head]):
            if i:
                at = _expect(tokens, at, ",", text)
            node, at = _parse_at(tokens, at, text, kind)
            args.append(node)
        node = Node(head, tuple(args))
        return _checked(node, want, text), _expect(tokens, at, ")", text)
    if head.startswith("{"):
        return _checked(Node("nom", (head[1:-1],)), want, text), at + 1
    if head == "top":
        return _checked(TOP, want, text), at + 1
    if not head[0].isalpha() and head[0] != "_":
        raise GrammarError(f"feature {text[:80]!r}: unexpected {head!r}")
    if at + 1 < len(tokens) and tokens[at + 1].startswith("["):
        return _checked(Node("proj", (head, int(tokens[at + 1][1]))), want, text), at + 2
    node = Node("role", (head,)) if want == "r" else Node("pred", (head,))
    return node, at + 1


def _checked(node: Node, want: str | None, text: str) -> Node:
    if want is not None and node.is_role != (want == "r"):
        raise GrammarError(f"feature {text[:80]!r}: {node.text()} is a {'role' if node.is_role else 'concept'} "
                           f"where a {'role' if want == 'r' else 'concept'} is expected")
    return node


def _expect(tokens: list[str], at: int, token: str, text: str) -> int:
    if at >= len(tokens) or tokens[at] != token:
        raise GrammarError(f"feature {text[:80]!r}: expected {token!r}")
    return at + 1


__all__ = ["CONCEPT_OPS", "MAX_DEPTH", "MAX_LENGTH", "ROLE_OPS", "TOP", "GrammarError", "Node", "parse", "pred", "role"]
