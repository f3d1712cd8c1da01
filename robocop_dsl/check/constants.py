"""``let NAME = VALUE``: constants, checked where they are declared.

A constant's value is checked for what does not depend on its use (units, numbers too
large, the names it reads, an offset's body and vector); where it is used, the use
decides whether it fits. A constant whose value is wrong is reported once, at its
``let``: its uses then stand for any value (``ctx.generic``), so that the problem is not
reported again wherever it is used.
"""

from __future__ import annotations

from ..diagnostics import did_you_mean
from ..lang import ast
from ..lang.catalogue import FEEDBACKS, INTERPOLATORS
from .behaviors import WORDS, kind_of_name
from .bindings import Binding, substitute
from .context import CheckContext, finite
from .parameters import check_body
from .values import check_offset, unit_of

_LARGEST = "numbers are at most about 1.8e308"


def declared_constants(ctx: CheckContext, mission: ast.Mission) -> dict[str, Binding]:
    """The usable constants in order, each substituted with the ones before it. Sets
    ``ctx.constants`` (every declared one) and adds the wrong ones to ``ctx.generic``."""
    lets: dict[str, Binding] = {}
    declared: dict[str, ast.Let] = {}
    ctx.constants = declared
    order = {let.name.text: let for let in reversed(mission.of_type(ast.Let))}
    for let in mission.of_type(ast.Let):
        name = let.name.text
        if name in declared:
            ctx.error("duplicate-name", f"constant '{name}' is already declared",
                      let.name.span, f"first declared at {ctx.where(declared[name].span)}")
            continue
        declared[name] = let
        if ctx.measure_name(let.name, "constant"):
            continue
        kind = kind_of_name(ctx, name)
        if kind in ("task", "constraint", "event"):
            first = ctx.symbols.tasks.get(name) or ctx.symbols.constraints.get(name)
            where = f": it is declared at {ctx.where(first.name.span)}" if first else ""
            ctx.error("duplicate-name", f"constant '{name}' has the name of a {kind}",
                      let.name.span, f"give it a name of its own{where}")
            continue
        value = substitute(ctx, let.value, lets)
        if _check_constant(ctx, let, value, order):
            lets[name] = Binding(name, value, let.span)
        else:
            ctx.generic |= {name}
    return lets


def _check_constant(ctx: CheckContext, let: ast.Let, value, order: dict) -> bool:
    """Report what is wrong with a constant's value whatever it is used for."""
    what = f"constant '{let.name.text}'"
    if isinstance(value, ast.Quantity):
        if unit_of(ctx, value.unit) is False:
            return False
        if not finite(value.value):
            ctx.error("bad-number", f"{what} is too large", value.span, _LARGEST)
            return False
    elif isinstance(value, ast.Vector):
        if not all(isinstance(v, float) for v in value.values):
            return False
        if unit_of(ctx, value.unit) is False:
            return False
        if not all(map(finite, value.values)):
            ctx.error("bad-number", f"{what} has a value too large", value.span, _LARGEST)
            return False
    elif isinstance(value, ast.Reference):
        return _check_reference(ctx, let, value.name, order)
    elif isinstance(value, ast.Offset):
        if not check_body(ctx, value.body):
            return False
        return check_offset(ctx, value) is not None
    return True


def _check_reference(ctx: CheckContext, let: ast.Let, name: ast.Name, order: dict) -> bool:
    text = name.text
    if text in ctx.generic:
        return False
    if text == let.name.text:
        ctx.error("unknown-name", f"constant '{text}' reads itself", name.span,
                  "give it a value: a quantity, a vector, a body, 'BODY offset VECTOR' or "
                  "pose(...)")
        return False
    later = order.get(text)
    if later is not None and text not in ctx.constants:
        ctx.error("unknown-name", f"constant '{text}' is used before it is declared",
                  name.span, f"'{text}' is declared at {ctx.where(later.span)}: a constant "
                  "reads the constants declared before it")
        return False
    if text in WORDS or text in INTERPOLATORS.names() or text in FEEDBACKS.names() \
            or not ctx.world.known or kind_of_name(ctx, text) is not None:
        return True
    candidates = [*ctx.world.body_names(), *ctx.symbols.controlled(), *ctx.symbols.events,
                  *(n for n in ctx.constants if n != let.name.text)]
    ctx.error("unknown-name", f"unknown name '{text}'", name.span,
              did_you_mean(text, candidates) or "a constant names a value: a quantity, a "
              "vector, a body, 'BODY offset VECTOR' or pose(...)")
    return False
