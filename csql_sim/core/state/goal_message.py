"""The goal form of the state message: the goal block by block, so that ``#`` can generalize across goals.

The paper's message (:mod:`csql_sim.core.state.message`, the *index form*, still the default)
names the goal by one index character, so every Q-classifier is specific to one goal.
The goal form keeps the state part character for character and replaces the goal code
by a description of the goal configuration, then optional detector fields::

    S  k  cccccc  oooooo  h  G  pppppp  q  [dddddd ...]

* ``S k cccccc oooooo h``: the index form's tag, action slot, clear field, on field and
  held block, unchanged.
* ``G``: the tag of the goal part.
* ``pppppp``: per block A..F, what it must stand on in the goal: ``t`` the table,
  ``a``..``f`` a block, ``0`` held (the goal holds it); ``0`` for blocks beyond n.
* ``q``: the block the goal holds, ``a``..``f``, or ``0`` (none).
* detector fields, six characters each (``1`` true, ``0`` false; ``0`` beyond n), in
  the order of :data:`DETECTORS`, those the form carries:

  - ``home``: the block stands on what it must stand on in the goal (held and held in
    the goal counts);
  - ``placed``: home, and what it stands on is the table or a placed block (for held:
    held in the goal) -- the classic "well placed";
  - ``ready``: its goal place is ready: its goal support is the table, or a placed block
    that is clear now (``0`` when the goal holds it).

Every detector is computed from the state and the goal alone, about one block and what
it (or its goal support) stands on: no distance, plan or action is in the message. The
length is ``index form length - goal_width + 8 + 6 * detectors`` (n = 3 with all three
detectors: 41 characters).

A rule file in the goal form records ``meta: {form: goal, detectors: [...]}``
(:meth:`GoalForm.meta`, read back by :func:`form_of`); files without ``form`` are in the
index form.
"""

from __future__ import annotations

from dataclasses import dataclass

from csql_sim.core.state.goal_relations import placed_from
from csql_sim.core.state.message import (
    BLOCK_FIELD,
    MessageError,
    _check_clear_and_held,
    _fail,
    _parse_action_slot,
    _parse_on_field,
    _supports,
    encode_code,
    layout,
)
from csql_sim.core.state.world import BLOCK_NAMES, HAND, TABLE, State, WorldError, check_n

INDEX_FORM = "index"
GOAL_FORM = "goal"
FORMS = (INDEX_FORM, GOAL_FORM)
DETECTORS = ("home", "placed", "ready")
"""Every detector field, in message order."""
GOAL_TAG = "G"
WILDCARD = "#"


@dataclass(frozen=True)
class GoalForm:
    """The layout of goal-form messages for n blocks with some detector fields.

    Attributes:
        n: number of blocks.
        detectors: the detector fields carried, a sub-sequence of :data:`DETECTORS`.
    """

    n: int
    detectors: tuple[str, ...] = DETECTORS

    def __post_init__(self) -> None:
        check_n(self.n)
        unknown = [d for d in self.detectors if d not in DETECTORS]
        if unknown:
            raise MessageError(f"unknown detector {unknown[0]!r}; choose from {', '.join(DETECTORS)}")
        if tuple(d for d in DETECTORS if d in self.detectors) != tuple(self.detectors):
            raise MessageError(f"detectors must be distinct and in the order {', '.join(DETECTORS)}, "
                               f"got {', '.join(self.detectors)}")

    @property
    def state_end(self) -> int:
        """End of the state part (the index form without its goal code)."""
        return layout(self.n).goal_start

    @property
    def tag_pos(self) -> int:
        return self.state_end

    @property
    def goal_on_start(self) -> int:
        return self.tag_pos + 1

    @property
    def goal_held_pos(self) -> int:
        return self.goal_on_start + BLOCK_FIELD

    def detector_start(self, name: str) -> int:
        """First position of a detector field."""
        return self.goal_held_pos + 1 + BLOCK_FIELD * self.detectors.index(name)

    @property
    def length(self) -> int:
        """Length of a goal-form state message."""
        return self.goal_held_pos + 1 + BLOCK_FIELD * len(self.detectors)

    def meta(self) -> dict:
        """What a rule file in this form records in its ``meta``."""
        return {"form": GOAL_FORM, "detectors": list(self.detectors)}

    def field_names(self) -> list[str]:
        """A short name for every position (``on[A]``, ``goal[B]``, ``placed[C]``, ...), for messages."""
        lay, names = layout(self.n), []
        names += ["tag"] + ["action"] * lay.action_width
        names += [f"clear[{b}]" for b in BLOCK_NAMES] + [f"on[{b}]" for b in BLOCK_NAMES] + ["held"]
        names += ["goal-tag"] + [f"goal[{b}]" for b in BLOCK_NAMES] + ["goal-held"]
        for d in self.detectors:
            names += [f"{d}[{b}]" for b in BLOCK_NAMES]
        return names


def form_of(meta: dict, n: int, source: str = "rule file") -> GoalForm | None:
    """The goal form a rule file's meta records, or None for the index form (and older files)."""
    form = meta.get("form", INDEX_FORM)
    if form == INDEX_FORM:
        return None
    if form != GOAL_FORM:
        raise MessageError(f"{source}: meta.form must be one of {', '.join(FORMS)}, got {form!r}")
    detectors = meta.get("detectors", [])
    if not isinstance(detectors, list) or not all(isinstance(d, str) for d in detectors):
        raise MessageError(f"{source}: meta.detectors must be a list of detector names")
    return GoalForm(n, tuple(detectors))


def detector_values(state: State, goal: State) -> dict[str, tuple[bool, ...]]:
    """Every detector of :data:`DETECTORS` for each block of ``state`` towards ``goal``."""
    if state.n != goal.n:
        raise WorldError(f"state has {state.n} blocks but goal has {goal.n}")
    home = tuple(s == g for s, g in zip(state.support, goal.support, strict=True))
    placed_all = placed_from(home, state.support)
    ready = tuple(g == TABLE or (g >= 0 and placed_all[g] and state.is_clear(g)) for g in goal.support)
    return {"home": home, "placed": placed_all, "ready": ready}


def _support_char(support: int) -> str:
    if support == TABLE:
        return "t"
    if support == HAND:
        return "0"
    return BLOCK_NAMES[support].lower()


def format_goal_message(state: State, goal: State, form: GoalForm | None = None, action_code: int = 0) -> str:
    """The goal-form state message of ``state`` towards ``goal`` (all detectors unless ``form`` says)."""
    form = form or GoalForm(state.n)
    if state.n != form.n or goal.n != form.n:
        raise WorldError(f"the form is for {form.n} blocks, the state has {state.n} and the goal {goal.n}")
    lay = layout(form.n)
    clear = "".join("1" if state.is_clear(i) else "0" for i in range(form.n))
    held = state.held
    text = ("S" + encode_code(action_code, lay.action_width) + clear.ljust(BLOCK_FIELD, "0")
            + "".join(_support_char(s) for s in state.support).ljust(BLOCK_FIELD, "0")
            + (BLOCK_NAMES[held].lower() if held is not None else "0"))
    goal_held = goal.held
    text += (GOAL_TAG + "".join(_support_char(s) for s in goal.support).ljust(BLOCK_FIELD, "0")
             + (BLOCK_NAMES[goal_held].lower() if goal_held is not None else "0"))
    values = detector_values(state, goal)
    for name in form.detectors:
        text += "".join("1" if v else "0" for v in values[name]).ljust(BLOCK_FIELD, "0")
    return text


@dataclass(frozen=True)
class GoalMessage:
    """A parsed goal-form message.

    Attributes:
        state: the configuration.
        goal: the goal configuration.
        action_code: the action slot (0 for none).
    """

    state: State
    goal: State
    action_code: int


def parse_goal_message(message: str, form: GoalForm) -> GoalMessage:
    """Parse a goal-form message; the inverse of :func:`format_goal_message`.

    Raises:
        MessageError: one line naming the first bad position and its character (a
            detector field that disagrees with the state and goal is malformed too).
    """
    if len(message) != form.length:
        raise MessageError(f"malformed goal-form message {message!r}: {len(message)} characters, expected "
                           f"{form.length} for n={form.n} with detectors {','.join(form.detectors) or 'none'}")
    lay = layout(form.n)
    if message[0] != "S":
        raise _fail(message, 0, "'S'")
    code = _parse_action_slot(message, lay)
    support = _parse_on_field(message, lay)
    state = _checked_state(message, support)
    _check_clear_and_held(message, lay, state)
    if message[form.tag_pos] != GOAL_TAG:
        raise _fail(message, form.tag_pos, repr(GOAL_TAG))
    goal = _checked_state(message, _goal_support(message, form))
    want = format_goal_message(state, goal, form, code)
    for pos in range(form.goal_held_pos, form.length):
        if message[pos] != want[pos]:
            raise _fail(message, pos, f"{want[pos]!r} ({form.field_names()[pos]} of this state and goal)")
    return GoalMessage(state, goal, code)


def _goal_support(message: str, form: GoalForm) -> list[int]:
    """What each block stands on in the goal, from the goal's on field."""
    return _supports(message, form.goal_on_start, form.n)


def _checked_state(message: str, support: list[int]) -> State:
    try:
        return State(tuple(support))
    except WorldError as exc:
        raise MessageError(f"malformed goal-form message {message!r}: {exc}") from None


def is_goal_message(text: str) -> bool:
    """A cheap test: a state message with the goal tag where its n puts it, long enough for the goal form."""
    return text[:1] == "S" and any(len(text) >= form.length and text[form.tag_pos] == GOAL_TAG
                                   for form in (GoalForm(n, ()) for n in _block_counts(text)))


def read_goal_message(text: str, n: int | None = None) -> GoalMessage:
    """Parse a goal-form message whose n and detectors are read from it (each detector field is six wide).

    The detectors carried are the first k of :data:`DETECTORS` for the k its length gives.

    Raises:
        MessageError: one line, when no n and number of detectors fits, or as :func:`parse_goal_message`.
    """
    for blocks in ([n] if n is not None else _block_counts(text)):
        bare = GoalForm(blocks, ())
        extra = len(text) - bare.length
        if len(text) > bare.tag_pos and text[bare.tag_pos] == GOAL_TAG and extra % BLOCK_FIELD == 0 \
                and 0 <= extra // BLOCK_FIELD <= len(DETECTORS):
            return parse_goal_message(text, GoalForm(blocks, DETECTORS[: extra // BLOCK_FIELD]))
    raise MessageError(f"malformed goal-form message {text!r}: {len(text)} characters with the goal tag "
                       f"{GOAL_TAG!r} fit no 2..6-block layout")


def _block_counts(text: str) -> list[int]:
    """The n a state part can describe: blocks on something or held, for each action-slot width."""
    out = []
    for width in (1, 2):
        on_start = 1 + width + BLOCK_FIELD
        on, held = text[on_start: on_start + BLOCK_FIELD], text[on_start + BLOCK_FIELD: on_start + BLOCK_FIELD + 1]
        blocks = sum(ch != "0" for ch in on) + (held not in ("", "0"))
        if 2 <= blocks <= 6 and layout(blocks).action_width == width:
            out.append(blocks)
    return out


def pattern_problem(pattern: str, form: GoalForm) -> str | None:
    """Why ``pattern`` is not a goal-form condition (``#`` or a character its position allows); None if it is."""
    if len(pattern) != form.length:
        return f"condition {pattern!r} has {len(pattern)} characters, a goal-form condition has {form.length}"
    allowed = allowed_chars(form)
    for pos, ch in enumerate(pattern):
        if ch != WILDCARD and ch not in allowed[pos]:
            return (f"condition {pattern!r}: position {pos} ({form.field_names()[pos]}) is {ch!r}, "
                    f"expected # or one of {''.join(allowed[pos])}")
    return None


def allowed_chars(form: GoalForm) -> list[str]:
    """The characters each position of a goal-form message can hold."""
    lay, n = layout(form.n), form.n
    names = BLOCK_NAMES[:n].lower()
    out = ["S"] + ["0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"] * lay.action_width
    out += ["01" if i < n else "0" for i in range(BLOCK_FIELD)]
    out += ["t0" + names if i < n else "0" for i in range(BLOCK_FIELD)] + ["0" + names]
    out += [GOAL_TAG] + ["t0" + names if i < n else "0" for i in range(BLOCK_FIELD)] + ["0" + names]
    for _ in form.detectors:
        out += ["01" if i < n else "0" for i in range(BLOCK_FIELD)]
    return out


__all__ = ["DETECTORS", "FORMS", "GOAL_FORM", "INDEX_FORM", "GoalForm", "GoalMessage", "allowed_chars",
           "detector_values", "form_of", "format_goal_message", "is_goal_message", "parse_goal_message",
           "pattern_problem", "read_goal_message"]
