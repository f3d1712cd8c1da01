"""Rebuild syntax trees: the one traversal that tagging imported files and binding
constants and behaviour parameters share."""

from __future__ import annotations

import dataclasses
from typing import Callable

from ..diagnostics import Span
from ..lang import ast


def rebuild(node, visit: Callable):
    """``node`` rebuilt bottom-up: every child node (in fields and tuples) first, then
    ``visit(node)`` on the node with its new children. Unchanged subtrees are kept."""
    if isinstance(node, tuple):
        items = tuple(rebuild(item, visit) for item in node)
        return node if all(a is b for a, b in zip(items, node)) else items
    if not isinstance(node, ast.Node):
        return node
    changes = {}
    for field in dataclasses.fields(node):
        if field.name == "span":
            continue
        value = getattr(node, field.name)
        new = rebuild(value, visit)
        if new is not value:
            changes[field.name] = new
    return visit(dataclasses.replace(node, **changes) if changes else node)


def in_file(node, path: str):
    """``node`` with every span naming the file ``path`` (for a tree of an imported file)."""
    def tag(child):
        span = child.span
        if span.file == path:
            return child
        return dataclasses.replace(child, span=dataclasses.replace(span, file=path))
    return rebuild(node, tag)


def at(node, span: Span):
    """``node`` with every span replaced by ``span`` (a value substituted where it is
    used, so that problems with it are reported there)."""
    return rebuild(node, lambda child: dataclasses.replace(child, span=span))
