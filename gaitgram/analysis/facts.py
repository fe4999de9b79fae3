"""Facts about every rule, computed once per grammar in linear or near-linear time.

Used by the linter, the mapper (minimum depths for initialisation) and the
language server (hover). No algorithm here can loop on a grammar: they are
worklists over a finite graph, so a rule that never terminates is a fact
(``productive`` is false), not a hang.

Depth convention: a rule expanded into terminals only has depth 1; a choice has
depth 1 + the largest depth of the rules it uses. Terminals add no depth.
"""

from __future__ import annotations

import heapq
from collections import deque
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import TypeVar

from gaitgram.analysis.cfg import Cfg, Item, RuleKind, build_cfg
from gaitgram.language.model import Grammar

INFINITE = float("inf")

Value = TypeVar("Value", int, float)


@dataclass(frozen=True, slots=True)
class RuleFacts:
    name: str
    productive: bool
    reachable: bool
    min_depth: int | None  # None when the rule cannot finish
    recursive: bool
    choices: int
    choice_min_depths: tuple[int | None, ...]


@dataclass(frozen=True, eq=False)
class GrammarFacts:
    cfg: Cfg
    productive: tuple[bool, ...]
    reachable: tuple[bool, ...]
    min_depth: tuple[int | None, ...]
    choice_min_depth: tuple[tuple[int | None, ...], ...]
    #: For each @joint rule, the rules its curve can use (itself included).
    joint_reach: Mapping[str, frozenset[str]]

    @cached_property
    def recursive(self) -> tuple[bool, ...]:
        """Computed when first asked: the linter never asks, and on a large grammar it is a
        fifth of ``check``'s time (the language server re-checks on every edit)."""
        return recursive_rules(self.cfg)

    def rule(self, name: str) -> RuleFacts | None:
        i = self.cfg.index.get(name)
        if i is None:
            return None
        return RuleFacts(
            name=name,
            productive=self.productive[i],
            reachable=self.reachable[i],
            min_depth=self.min_depth[i],
            recursive=self.recursive[i],
            choices=len(self.cfg.choices[i]),
            choice_min_depths=self.choice_min_depth[i],
        )

    @cached_property
    def start_productive(self) -> bool:
        return self.cfg.start is not None and self.productive[self.cfg.start]


def analyse(grammar: Grammar, cfg: Cfg | None = None) -> GrammarFacts:
    if cfg is None:
        cfg = build_cfg(grammar)
    depth, choice_depth = min_depths(cfg)
    productive = tuple(d is not None for d in depth)
    reachable = reachable_from(cfg, [] if cfg.start is None else [cfg.start])
    return GrammarFacts(
        cfg=cfg,
        productive=productive,
        reachable=reachable,
        min_depth=depth,
        choice_min_depth=choice_depth,
        joint_reach=JointReach(cfg, [joint.rule for joint in grammar.joints]),
    )


class JointReach(Mapping[str, frozenset[str]]):
    """For each ``@joint`` rule, the rules its curve can use, each found when first read.

    One search of the grammar per joint rule: worked out eagerly, a grammar of thousands of
    joint rules cost their number times its size on every check, which reads none of them."""

    def __init__(self, cfg: Cfg, rules: Iterable[str]) -> None:
        self._cfg = cfg
        self._roots = {rule: root for rule in rules if (root := cfg.index.get(rule)) is not None}
        self._found: dict[str, frozenset[str]] = {}

    def __getitem__(self, rule: str) -> frozenset[str]:
        found = self._found.get(rule)
        if found is None:
            cfg = self._cfg
            seen = reachable_from(cfg, [self._roots[rule]])
            found = self._found[rule] = frozenset(
                cfg.names[i] for i, hit in enumerate(seen) if hit and cfg.kinds[i] is RuleKind.DEFINED
            )
        return found

    def __iter__(self) -> Iterator[str]:
        return iter(self._roots)

    def __len__(self) -> int:
        return len(self._roots)


def min_depths(
    cfg: Cfg, assume_productive: Iterable[int] = ()
) -> tuple[tuple[int | None, ...], tuple[tuple[int | None, ...], ...]]:
    """Minimum derivation depth of every rule and choice (None: cannot finish).

    Knuth's generalisation of Dijkstra's algorithm: a choice's depth is known
    once the depth of its last rule is, and rules leave the heap in order of
    depth, so that last one is also the deepest. ``assume_productive`` rules are
    treated as finishing at depth 1 (the linter uses it for undefined names, so
    that one missing rule is reported once, not as a cascade).
    """
    assume = [(1, r) for r in assume_productive]
    depth, choice_depth = _least_values(cfg.choices, [1] * len(cfg), assume, summing=False)
    return tuple(depth), choice_depth


def _least_values(
    rules: Sequence[Sequence[Sequence[Item]]],
    extra: Sequence[Value],
    seeds: Iterable[tuple[Value, int]],
    *,
    summing: bool,
) -> tuple[tuple[Value | None, ...], tuple[tuple[Value | None, ...], ...]]:
    """The least value of each rule (its choices, by rule number) and of each choice (None: it
    cannot finish), where a choice of rule ``r`` is worth ``extra[r]`` plus the values of the rules
    it uses: their sum when ``summing``, else the largest. ``seeds`` give rules a value at the start.

    Knuth's generalisation of Dijkstra's algorithm: a choice's value is known once that of its last
    rule is, and rules leave the heap in order of value, so that last one is also the largest.
    """
    n = len(rules)
    # Choices are numbered across the grammar: flat lists index faster than nested ones.
    owner: list[int] = []
    first_choice: list[int] = []
    remaining: list[int] = []  # rules a choice waits for, each occurrence once
    users: list[list[int]] = [[] for _ in range(n)]  # the choices that wait for a rule
    heap = list(seeds)
    choice_value: list[Value | None] = []
    for r, choices in enumerate(rules):
        first_choice.append(len(owner))
        seeded = False  # its choices without rules are all worth extra[r]: one heap entry for them
        for choice in choices:
            waits = 0
            for item in choice:
                if item.__class__ is int:
                    users[item].append(len(owner))
                    waits += 1
            owner.append(r)
            remaining.append(waits)
            choice_value.append(None if waits else extra[r])
            if not waits and not seeded:
                heap.append((extra[r], r))
                seeded = True
    first_choice.append(len(owner))
    value: list[Value | None] = [None] * n
    total: list[Value] = [0] * len(owner)
    heapq.heapify(heap)
    while heap:
        v, r = heapq.heappop(heap)
        if value[r] is not None:
            continue
        value[r] = v
        for c in users[r]:
            remaining[c] -= 1
            if summing:
                total[c] += v
            if remaining[c] == 0:
                u = owner[c]
                found = choice_value[c] = (total[c] if summing else v) + extra[u]
                if value[u] is None:
                    heapq.heappush(heap, (found, u))
    by_rule = tuple(tuple(choice_value[first_choice[r] : first_choice[r + 1]]) for r in range(n))
    return tuple(value), by_rule


def reachable_from(cfg: Cfg, roots: Iterable[int]) -> tuple[bool, ...]:
    seen = [False] * len(cfg)
    queue = deque()
    for root in roots:
        if not seen[root]:
            seen[root] = True
            queue.append(root)
    while queue:
        r = queue.popleft()
        for choice in cfg.choices[r]:
            for item in choice:
                if isinstance(item, int) and not seen[item]:
                    seen[item] = True
                    queue.append(item)
    return tuple(seen)


def recursive_rules(cfg: Cfg) -> tuple[bool, ...]:
    """Rules that can derive themselves: members of a cycle (iterative Tarjan)."""
    n = len(cfg)
    successors = [sorted(cfg.children(r)) for r in range(n)]
    index = [-1] * n
    low = [0] * n
    on_stack = [False] * n
    stack: list[int] = []
    result = [False] * n
    counter = 0
    for root in range(n):
        if index[root] != -1:
            continue
        work = [(root, 0)]
        while work:
            v, i = work.pop()
            if i == 0:
                index[v] = low[v] = counter
                counter += 1
                stack.append(v)
                on_stack[v] = True
            recurse = False
            for j in range(i, len(successors[v])):
                w = successors[v][j]
                if index[w] == -1:
                    work.append((v, j + 1))
                    work.append((w, 0))
                    recurse = True
                    break
                if on_stack[w]:
                    low[v] = min(low[v], index[w])
            if recurse:
                continue
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on_stack[w] = False
                    component.append(w)
                    if w == v:
                        break
                if len(component) > 1 or v in successors[v]:
                    for w in component:
                        result[w] = True
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[v])
    return tuple(result)


def _usable(cfg: Cfg, productive: tuple[bool, ...]) -> list[list[tuple[Item, ...]]]:
    """Each rule's choices that can finish: every rule they use is productive."""
    return [
        [choice for choice in choices if all(productive[i] for i in choice if isinstance(i, int))]
        for choices in cfg.choices
    ]


def derived_exactly_once(
    cfg: Cfg, productive: tuple[bool, ...], usable: list[list[tuple[Item, ...]]] | None = None
) -> frozenset[int]:
    """Rules that every finishing derivation uses exactly once, found without a search: the start
    rule when nothing uses it, and a rule used at one place only, in the one usable choice of a
    rule that is itself derived exactly once. A cheap test before :func:`occurrence_bounds` (one
    search per joint rule), which it agrees with wherever it answers (a property test keeps them
    equal); a rule it leaves out may still be derived once."""
    start = cfg.start
    if start is None or not productive[start]:
        return frozenset()
    if usable is None:
        usable = _usable(cfg, productive)
    uses: list[list[int]] = [[] for _ in range(len(cfg))]  # each place a rule is used: its user
    for r, choices in enumerate(usable):
        for choice in choices:
            for i in choice:
                if isinstance(i, int):
                    uses[i].append(r)
    if uses[start]:
        return frozenset()
    once = {start}
    frontier = [start]
    while frontier:
        r = frontier.pop()
        if len(usable[r]) != 1:
            continue
        for i in usable[r][0]:
            if isinstance(i, int) and i not in once and uses[i] == [r]:
                once.add(i)
                frontier.append(i)
    return frozenset(once)


def occurrence_bounds(cfg: Cfg, target: int, productive: tuple[bool, ...]) -> tuple[float, float]:
    """How many times ``target`` can occur in a derivation from the start: (fewest, most).

    Only finishing derivations count, so only choices whose rules are all
    productive are followed. ``most`` is infinite when a cycle can repeat it.
    """
    return Occurrences(cfg, productive).bounds(target)


class Occurrences:
    """:func:`occurrence_bounds` for many targets of one grammar (the linter asks for each joint
    rule): the usable choices and where each rule occurs in them are found once, and each
    target's bounds are worked out over the rules that can reach it only. A choice that uses none
    of them derives the target no time, so only the places those rules occur are read, not the
    whole grammar per target (thousands of joint rules cost their number times its size)."""

    def __init__(self, cfg: Cfg, productive: tuple[bool, ...]) -> None:
        self.cfg = cfg
        self.productive = productive
        self.usable = _usable(cfg, productive)
        #: For each rule, each place it occurs in a usable choice: (the user, the choice's index).
        self.places: list[list[tuple[int, int]]] = [[] for _ in range(len(cfg))]
        for r, choices in enumerate(self.usable):
            for c, choice in enumerate(choices):
                for i in choice:
                    if isinstance(i, int):
                        self.places[i].append((r, c))

    def bounds(self, target: int) -> tuple[float, float]:
        start = self.cfg.start
        if start is None or not self.productive[start]:
            return 0, 0
        # The rules that can reach the target (itself included), and for each of their choices
        # that uses some of them, which (once per occurrence).
        places = self.places
        reaching = {target}
        queue = deque([target])
        marked: dict[int, dict[int, list[int]]] = {}
        while queue:
            r = queue.popleft()
            for user, c in places[r]:
                marked.setdefault(user, {}).setdefault(c, []).append(r)
                if user not in reaching:
                    reaching.add(user)
                    queue.append(user)
        if start not in reaching:
            return 0.0, 0.0
        return self._fewest(target, reaching, marked), self._most(target, start, marked)

    def _fewest(self, target: int, reaching: set[int], marked: dict[int, dict[int, list[int]]]) -> float:
        """As ``min_depths``, with sums instead of maxima, over the rules that reach the target:
        a choice using none of them is worth nothing but the target itself."""
        usable = self.usable
        waiting: dict[int, list[tuple[int, int]]] = {}  # a rule: the (user, choice) that wait for it
        remaining: dict[tuple[int, int], int] = {}
        total: dict[tuple[int, int], float] = {}
        heap: list[tuple[float, int]] = []
        for r in reaching:
            own = 1.0 if r == target else 0.0
            choices = marked.get(r, {})
            if len(choices) < len(usable[r]):  # a choice that uses no rule reaching the target
                heap.append((own, r))
            for c, items in choices.items():
                remaining[r, c] = len(items)
                total[r, c] = own
                for i in items:
                    waiting.setdefault(i, []).append((r, c))
        heapq.heapify(heap)
        value: dict[int, float] = {}
        while heap:
            v, r = heapq.heappop(heap)
            if r in value:
                continue
            value[r] = v
            for key in waiting.get(r, ()):
                remaining[key] -= 1
                total[key] += v
                if remaining[key] == 0 and key[0] not in value:
                    heapq.heappush(heap, (total[key], key[0]))
        return value.get(self.cfg.start, 0.0)  # type: ignore[arg-type]  # start is set

    def _most(self, target: int, start: int, marked: dict[int, dict[int, list[int]]]) -> float:
        """Infinite through any cycle of rules that reach the target (each can repeat it), else
        the longest-path sum over them (memoised depth-first)."""
        most: dict[int, float] = {}
        state: dict[int, int] = {}  # absent new, 1 on the path, 2 done
        work: list[tuple[int, bool]] = [(start, False)]
        while work:
            r, done = work.pop()
            choices = marked.get(r, {})
            if done:
                best = max((sum(most[i] for i in items) for items in choices.values()), default=0.0)
                most[r] = best + (1.0 if r == target else 0.0)
                state[r] = 2
                continue
            if state.get(r) == 2:
                continue
            state[r] = 1
            work.append((r, True))
            for items in choices.values():
                for i in items:
                    seen = state.get(i)
                    if seen == 1:
                        return INFINITE
                    if seen is None:
                        work.append((i, False))
        return most.get(start, 0.0)
