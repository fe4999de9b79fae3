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
from collections.abc import Iterable, Sequence
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
    joint_reach: dict[str, frozenset[str]]

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
    joint_reach = {}
    for joint in grammar.joints:
        root = cfg.index.get(joint.rule)
        if root is not None:
            seen = reachable_from(cfg, [root])
            joint_reach[joint.rule] = frozenset(
                cfg.names[i] for i, hit in enumerate(seen) if hit and cfg.kinds[i] is RuleKind.DEFINED
            )
    return GrammarFacts(
        cfg=cfg,
        productive=productive,
        reachable=reachable,
        min_depth=depth,
        choice_min_depth=choice_depth,
        joint_reach=joint_reach,
    )


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
        for choice in choices:
            waits = 0
            for item in choice:
                if item.__class__ is int:
                    users[item].append(len(owner))
                    waits += 1
            owner.append(r)
            remaining.append(waits)
            choice_value.append(None if waits else extra[r])
            if not waits:
                heap.append((extra[r], r))
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


def derived_exactly_once(cfg: Cfg, productive: tuple[bool, ...]) -> frozenset[int]:
    """Rules that every finishing derivation uses exactly once, found without a search: the start
    rule when nothing uses it, and a rule used at one place only, in the one usable choice of a
    rule that is itself derived exactly once. A cheap test before :func:`occurrence_bounds` (one
    search per joint rule), which it agrees with wherever it answers (a property test keeps them
    equal); a rule it leaves out may still be derived once."""
    start = cfg.start
    if start is None or not productive[start]:
        return frozenset()
    usable = [
        [choice for choice in choices if all(productive[i] for i in choice if isinstance(i, int))]
        for choices in cfg.choices
    ]
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
    start = cfg.start
    if start is None or not productive[start]:
        return 0, 0
    usable = [
        [choice for choice in choices if all(productive[i] for i in choice if isinstance(i, int))]
        for choices in cfg.choices
    ]
    # Fewest: as min_depths, with sums instead of maxima.
    n = len(cfg)
    extra = [1.0 if r == target else 0.0 for r in range(n)]
    fewest, _ = _least_values(usable, extra, (), summing=True)

    # Most: infinite through any usable cycle that can still reach the target,
    # otherwise a longest-path sum over the acyclic rest (memoised depth-first).
    reaches_target = [False] * n
    reverse: list[list[int]] = [[] for _ in range(n)]
    for r in range(n):
        for choice in usable[r]:
            for i in choice:
                if isinstance(i, int):
                    reverse[i].append(r)
    queue = deque([target])
    reaches_target[target] = True
    while queue:
        r = queue.popleft()
        for p in reverse[r]:
            if not reaches_target[p]:
                reaches_target[p] = True
                queue.append(p)
    most: dict[int, float] = {}
    state = [0] * n  # 0 new, 1 on the path, 2 done
    work: list[tuple[int, bool]] = [(start, False)]
    while work:
        r, done = work.pop()
        if done:
            best = 0.0
            for choice in usable[r]:
                total = sum(most[i] for i in choice if isinstance(i, int) and reaches_target[i])
                best = max(best, total)
            most[r] = best + (1.0 if r == target else 0.0)
            state[r] = 2
            continue
        if state[r] == 2 or not reaches_target[r]:
            most.setdefault(r, 0.0)
            continue
        if state[r] == 1:
            return fewest[start] or 0.0, INFINITE
        state[r] = 1
        work.append((r, True))
        for choice in usable[r]:
            for i in choice:
                if isinstance(i, int) and reaches_target[i]:
                    if state[i] == 1:
                        return fewest[start] or 0.0, INFINITE
                    if state[i] == 0:
                        work.append((i, False))
    return fewest[start] or 0.0, most.get(start, 0.0)
