"""Which of a frame's drawings share cells: rectangles of cells in groups that do not overlap.

A frame is drawn as blocks of cells, each block one group of drawings (robots, bursts, badges)
whose cell rectangles (x0, y0, x1, y1; x1 and y1 exclusive) reach into each other; blocks are
cached by content and copied into the frame.
"""

from __future__ import annotations

from collections.abc import Sequence

Rect = tuple[int, int, int, int]

PAIRWISE = 48  # rectangles up to which they are compared pair by pair (fewer steps than cells then)


def rect_groups(rects: Sequence[Rect]) -> list[tuple[Rect, list[int]]]:
    """The rectangles in groups whose bounding rectangles do not overlap: each group's bounding
    rectangle and its members' indices in order. Rectangles that share a cell are grouped, then
    groups whose bounding rectangles share one, until none do (cells looked up, not pairs
    compared: thousands of robots)."""
    if len(set(rects)) == len(rects) and all(r[2] - r[0] == 1 and r[3] - r[1] == 1 for r in rects):
        return [(r, [k]) for k, r in enumerate(rects)]  # one cell each, each its own (the usual case)
    if len(rects) <= PAIRWISE:
        return _pairwise(rects)
    alone, rest = _clear_cells(rects)
    groups: dict[int, tuple[Rect, list[int]]] = {}
    owner: dict[tuple[int, int], int] = {}  # each cell's group (one that may since have been merged into another)

    def add(k: int) -> None:
        rect, members = rects[k], [k]
        while True:  # the grown rectangle can reach a group it did not touch before
            hit = next((owner[c] for c in cells(rect) if owner.get(c) in groups), None)
            if hit is None:
                break
            r, more = groups.pop(hit)
            rect = (min(rect[0], r[0]), min(rect[1], r[1]), max(rect[2], r[2]), max(rect[3], r[3]))
            members += more
        groups[k] = (rect, members)
        for c in cells(rect):
            owner[c] = k

    for k in rest:
        add(k)
    while True:  # a merged group's rectangle is wider than its members: it can reach a cell left alone
        reached = [k for k in alone if owner.get(rects[k][:2]) in groups]
        if not reached:
            break
        alone = [k for k in alone if owner.get(rects[k][:2]) not in groups]
        for k in reached:
            add(k)
    return [(rects[k], [k]) for k in alone] + [(rect, sorted(members)) for rect, members in groups.values()]


def _clear_cells(rects: Sequence[Rect]) -> tuple[list[int], list[int]]:
    """The rectangles of one cell that no other rectangle reaches (each its own group: most of a
    crowd's cells), and the others, by index: only those need grouping."""
    reached: dict[tuple[int, int], int] = {}
    for r in rects:
        if r[2] - r[0] == 1 and r[3] - r[1] == 1:
            reached[r[0], r[1]] = reached.get((r[0], r[1]), 0) + 1
        else:
            for c in cells(r):
                reached[c] = 2
    alone, rest = [], []
    for k, r in enumerate(rects):
        (alone if r[2] - r[0] == 1 and r[3] - r[1] == 1 and reached[r[0], r[1]] == 1 else rest).append(k)
    return alone, rest


def _pairwise(rects: Sequence[Rect]) -> list[tuple[Rect, list[int]]]:
    groups: list[tuple[Rect, list[int]]] = []
    for k, rect in enumerate(rects):
        members = [k]
        hit = [g for g in groups if overlap(rect, g[0])]
        while hit:  # a merged rectangle can reach a group it did not touch before
            for g in hit:
                groups.remove(g)
                r = g[0]
                rect = (min(rect[0], r[0]), min(rect[1], r[1]), max(rect[2], r[2]), max(rect[3], r[3]))
                members += g[1]
            hit = [g for g in groups if overlap(rect, g[0])]
        groups.append((rect, members))
    return [(rect, sorted(members)) for rect, members in groups]


def cells(rect: Rect) -> list[tuple[int, int]]:
    return [(x, y) for y in range(rect[1], rect[3]) for x in range(rect[0], rect[2])]


def any_overlap(rects: Sequence[Rect]) -> bool:
    """Whether two of the cell rectangles share a cell."""
    if len(rects) <= PAIRWISE:
        return any(overlap(a, b) for i, a in enumerate(rects) for b in rects[i + 1 :])
    seen: set[tuple[int, int]] = set()
    for r in rects:
        for cell in cells(r):
            if cell in seen:
                return True
            seen.add(cell)
    return False


def overlap(a: tuple[float, float, float, float], b: tuple[float, float, float, float]) -> bool:
    """Whether two boxes ``(x0, y0, x1, y1)`` (pixels, ends excluded) share any area."""
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
