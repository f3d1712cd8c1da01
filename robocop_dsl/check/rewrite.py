"""Rebuild syntax trees: the one traversal that tagging imported files and binding
constants and behaviour parameters share."""

from __future__ import annotations

import dataclasses
from typing import Callable

from ..diagnostics import Span
from ..lang import ast

_CHILDREN: dict[type, tuple[str, ...]] = {}
_FIELDS: dict[type, tuple[str, ...]] = {}


def child_fields(kind: type) -> tuple[str, ...]:
    """The fields of a node type that may hold nodes (every field but ``span``)."""
    names = _CHILDREN.get(kind)
    if names is None:
        names = tuple(name for name in _fields(kind) if name != "span")
        _CHILDREN[kind] = names
    return names


def _fields(kind: type) -> tuple[str, ...]:
    """Every field of a node type, in the order its ``__init__`` sets them."""
    names = _FIELDS.get(kind)
    if names is None:
        names = tuple(f.name for f in dataclasses.fields(kind))
        _FIELDS[kind] = names
    return names


def replace(node, **changes):
    """A copy of the frozen node ``node`` with ``changes`` (``dataclasses.replace``
    without re-running ``__init__``: the fields are known to be valid). The fields are
    set one by one, in ``__init__``'s order, so that the copy keeps them as compactly
    as a node built the usual way (reading ``__dict__`` would give each node a dict)."""
    new = object.__new__(type(node))
    for name in _fields(type(node)):
        object.__setattr__(new, name, changes[name] if name in changes else getattr(node, name))
    return new


def rebuild(node, visit: Callable, keep: Callable | None = None,
            kinds: frozenset[type] | None = None):
    """``node`` rebuilt bottom-up: every child node (in fields and tuples) first, then
    ``visit(node)`` on the node with its new children. Unchanged subtrees are kept, and
    so are the nodes for which ``keep(node)`` holds, unvisited. ``kinds``, when given,
    are the node types that ``visit`` may change: the others are not visited."""
    if isinstance(node, tuple):
        items = [rebuild(item, visit, keep, kinds) for item in node]
        for new, old in zip(items, node):
            if new is not old:
                return tuple(items)
        return node
    if not isinstance(node, ast.Node) or (keep is not None and keep(node)):
        return node
    changes = None
    kind = type(node)
    for name in _CHILDREN.get(kind) or child_fields(kind):
        value = getattr(node, name)
        if isinstance(value, (ast.Node, tuple)):
            new = rebuild(value, visit, keep, kinds)
            if new is not value:
                if changes is None:
                    changes = {}
                changes[name] = new
    if changes:
        node = replace(node, **changes)
    return visit(node) if kinds is None or kind in kinds else node


def in_file(node, path: str):
    """``node`` with every span naming the file ``path`` (for a tree of an imported file)."""
    def tag(child):
        span = child.span
        if span.file == path:
            return child
        return replace(child, span=Span(span.line, span.column, span.end_line,
                                        span.end_column, path))
    return rebuild(node, tag)


def at(node, span: Span):
    """``node`` with every span replaced by ``span`` (a value substituted where it is
    used, so that problems with it are reported there)."""
    return rebuild(node, lambda child: replace(child, span=span))
