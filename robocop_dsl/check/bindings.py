"""Substitute constants (``let``) and behaviour parameters where they are used.

A binding stands for a name (a task, constraint, body, joint group or event: the
argument's name replaces the parameter's wherever a name of that kind is read) or for a
value (a quantity, vector, body, offset, pose). A value takes the place of a bare name
used as a value, and inside a vector its number joins the others: the vector's own
unit applies to its bare numbers only and every element must share one dimension, so
the result is written in SI.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..diagnostics import Span, did_you_mean
from ..lang import ast
from ..lang.catalogue import AXES_PARAMETERS
from ..lang.units import DIMENSIONLESS, SI_SYMBOL, lookup
from .context import CheckContext
from .rewrite import at, rebuild

# Fields that read a name of something declared elsewhere (never a state or a field).
_NAME_FIELDS = {
    ast.Enable: ("names",), ast.Disable: ("names",), ast.Reset: ("names",),
    ast.Assign: ("owner",), ast.Member: ("owner",), ast.Attach: ("body", "parent"),
    ast.Detach: ("body",), ast.Emit: ("event",), ast.EventCondition: ("event",),
    ast.Offset: ("body",), ast.Distance: ("first", "second"),
    ast.Clearance: ("first", "second"), ast.Wrench: ("body",),
    ast.Contact: ("first", "second"),
}

# The node types that a substitution may change (the others only get new children).
_VISITED = frozenset({ast.Reference, ast.Variable, ast.Log, ast.Vector, *_NAME_FIELDS})


@dataclass(frozen=True)
class Binding:
    """A constant or a behaviour parameter: ``value`` is an :class:`ast.Name` for a
    name, else the value it stands for; ``span`` is where it was declared."""

    name: str
    value: object
    span: Span


def substitute(ctx: CheckContext, node, bindings: dict[str, Binding]):
    """``node`` with every use of ``bindings`` replaced; problems are reported (a name in
    a vector that nothing binds among them)."""
    def visit(child):
        kind = type(child)
        if kind is ast.Reference:
            return _value(child, bindings)
        if kind is ast.Variable:
            binding = bindings.get(child.name.text)
            if binding is not None and not isinstance(binding.value, (ast.Name,
                                                                      ast.Reference)):
                return at(binding.value, child.span)
            return child
        if kind is ast.Log:
            return _log(child, bindings)
        if kind is ast.Vector and any(isinstance(v, ast.NameElement) for v in child.values):
            return resolve_vector(ctx, child, bindings)
        fields = _NAME_FIELDS.get(kind)
        if fields:
            return _renamed(child, fields, bindings)
        return child
    return rebuild(node, visit, keep=_lists_axes, kinds=_VISITED)


def _lists_axes(node) -> bool:
    """A parameter that lists the world's axes (``axes = [x, z]``): names, no constants."""
    return type(node) is ast.Parameter and node.name.text in AXES_PARAMETERS


def _log(log: ast.Log, bindings: dict[str, Binding]) -> ast.Log:
    """A log text with the ``{NAME}`` of constants and parameters written in."""
    from ..lang.formatter import format_value

    def written(match):
        binding = bindings.get(match.group(1).strip())
        if binding is None or not isinstance(binding.value, (ast.Quantity, ast.Vector)):
            return match.group(0)
        return format_value(binding.value)

    from .variables import PLACEHOLDER

    text = PLACEHOLDER.sub(written, log.text)
    return log if text == log.text else dataclasses.replace(log, text=text)


def _bound_name(name: ast.Name, bindings: dict[str, Binding]) -> ast.Name:
    binding = bindings.get(name.text)
    if binding is None:
        return name
    value = binding.value
    if isinstance(value, ast.Reference):
        value = value.name
    return ast.Name(value.text, span=name.span) if isinstance(value, ast.Name) else name


def _renamed(node, fields, bindings: dict[str, Binding]):
    changes = {}
    for field in fields:
        value = getattr(node, field)
        new = (tuple(_bound_name(n, bindings) for n in value) if isinstance(value, tuple)
               else _bound_name(value, bindings))
        if new != value:
            changes[field] = new
    return dataclasses.replace(node, **changes) if changes else node


def _value(reference: ast.Reference, bindings: dict[str, Binding]):
    binding = bindings.get(reference.name.text)
    if binding is None:
        return reference
    if isinstance(binding.value, ast.Name):
        return ast.Reference(ast.Name(binding.value.text, span=reference.name.span),
                             span=reference.span)
    return at(binding.value, reference.span)


def resolve_vector(ctx: CheckContext, vector: ast.Vector,
                   bindings: dict[str, Binding]) -> ast.Vector:
    """A vector whose named elements are replaced by their numbers, in SI (a var's name
    stays, read when the vector is used); ``vector`` itself (names left in it) after
    reporting names that are not numbers."""
    unit = lookup(vector.unit.text) if vector.unit else None
    scale = unit.to_si if unit else 1.0
    dimensions = {unit.dimension} if unit else set()
    values, ok = [], True
    for element in vector.values:
        if not isinstance(element, ast.NameElement):
            values.append(element * scale)
            continue
        number = _element(ctx, element, bindings)
        if number is None:
            ok = False
            continue
        value, dimension = number
        if dimension is not None:
            dimensions.add(dimension)
        if isinstance(value, ast.NameElement):
            values.append(value)
            continue
        values.append(-value if element.negative else value)
    if not ok:
        return vector
    if len(dimensions) > 1:
        ctx.error("mixed-dimensions", "the elements of a vector must share one dimension, "
                  "not " + " and ".join(sorted(dimensions)), vector.span,
                  "a trailing unit applies to the bare numbers only")
        return vector
    dimension = next(iter(dimensions), None)
    symbol = SI_SYMBOL.get(dimension) if dimension not in (None, DIMENSIONLESS) else None
    return ast.Vector(tuple(values), ast.Name(symbol, span=vector.span) if symbol else None,
                      span=vector.span)


def _element(ctx: CheckContext, element: ast.NameElement, bindings: dict[str, Binding]):
    """``(value [SI], dimension or None)`` of a name in a vector (the element itself
    for a var), ``None`` after reporting a name that is not a number."""
    name = element.name
    binding = bindings.get(name.text)
    value = binding.value if binding is not None else None
    if binding is None and name.text in ctx.all_variables:
        return element, None
    if (binding is None and name.text in ctx.generic) or ctx.opaque(value):
        return 0.0, None
    if binding is None:
        numbers = [b.name for b in bindings.values() if isinstance(b.value, ast.Quantity)]
        ctx.error("unknown-name", f"unknown constant '{name.text}'", name.span,
                  did_you_mean(name.text, numbers) or "declare it: let NAME = VALUE")
        return None
    if not isinstance(value, ast.Quantity):
        ctx.error("wrong-value", f"'{name.text}' is not a number: it cannot stand in a "
                  "vector", name.span, f"'{name.text}' is declared at "
                  f"{ctx.where(binding.span)}")
        return None
    unit = lookup(value.unit.text) if value.unit else None
    if value.unit is not None and unit is None:
        return 0.0, None
    return value.value * (unit.to_si if unit else 1.0), unit.dimension if unit else None
