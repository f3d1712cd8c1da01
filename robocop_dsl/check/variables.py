"""Run-time values: ``var`` declarations, their assignments and the expressions they are
given, with dimensions checked like every other value.

A dimension is a tuple of exponents over metre, radian, second and newton, so that
``contact_z * 2``, ``distance(a, b) / elapsed`` or ``gain * force(tool).z`` have one;
a sum, a comparison and an assignment need equal dimensions. A value is a number or
a 3-vector (``BODY.position``, a ``position`` var). A ``count`` holds whole numbers.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ..diagnostics import did_you_mean
from ..lang import ast
from ..lang.units import (ADMITTANCE, ANGLE, ANGULAR_ACCELERATION, ANGULAR_JERK,
                          ANGULAR_VELOCITY, DIMENSIONLESS, FORCE, LENGTH,
                          LINEAR_ACCELERATION, LINEAR_JERK, LINEAR_VELOCITY, SI_SYMBOL, TIME,
                          TORQUE, lookup)
from .context import CheckContext

Dimension = tuple[int, int, int, int]
"""Exponents of m, rad, s and N."""
NONE: Dimension = (0, 0, 0, 0)
NAMED: dict[str, Dimension] = {
    DIMENSIONLESS: NONE, LENGTH: (1, 0, 0, 0), ANGLE: (0, 1, 0, 0), TIME: (0, 0, 1, 0),
    LINEAR_VELOCITY: (1, 0, -1, 0), ANGULAR_VELOCITY: (0, 1, -1, 0),
    LINEAR_ACCELERATION: (1, 0, -2, 0), ANGULAR_ACCELERATION: (0, 1, -2, 0),
    LINEAR_JERK: (1, 0, -3, 0), ANGULAR_JERK: (0, 1, -3, 0), FORCE: (0, 0, 0, 1),
    TORQUE: (1, 0, 0, 1), ADMITTANCE: (1, 0, -1, -1),
}
KINDS: dict[str, tuple[Dimension, int]] = {
    "count": (NONE, 1), "scalar": (NONE, 1), "length": (NAMED[LENGTH], 1),
    "angle": (NAMED[ANGLE], 1), "duration": (NAMED[TIME], 1), "force": (NAMED[FORCE], 1),
    "torque": (NAMED[TORQUE], 1), "linear_velocity": (NAMED[LINEAR_VELOCITY], 1),
    "angular_velocity": (NAMED[ANGULAR_VELOCITY], 1), "position": (NAMED[LENGTH], 3),
}
"""A var's kind: its dimension and size (a ``position`` is a 3-vector of lengths)."""
AXES = ("x", "y", "z")
PLACEHOLDER = re.compile(r"\{([^{}]*)\}")
"""``{NAME}`` in a ``log`` text: the value of a var or constant, with its unit."""
_MEASURABLE = "a number with a unit, a var, a constant or a measure"


@dataclass(frozen=True)
class Typed:
    """What an expression gives: its dimension, size (1 or 3) and whether it is a
    whole number."""

    dimension: Dimension
    size: int = 1
    whole: bool = False


@dataclass(frozen=True)
class VarInfo:
    """A declared var: its declaration and what it holds."""

    decl: ast.VarDecl
    typed: Typed


def describe(dimension: Dimension, size: int = 1) -> str:
    """``a length (m)``, ``a 3-vector of lengths (m)``, ``m^2/s`` for an unnamed one."""
    named = next((n for n, d in NAMED.items() if d == dimension), None)
    if named == DIMENSIONLESS:
        text = "a plain number"
    elif named is not None:
        text = f"{'an' if named[0] in 'aeiou' else 'a'} {named} ({SI_SYMBOL[named]})"
    else:
        text = symbol(dimension)
    return text if size == 1 else f"a 3-vector in {symbol(dimension) or 'plain numbers'}"


def symbol(dimension: Dimension) -> str:
    """The SI unit of a dimension: ``m``, ``N``, ``m*N/s^2``."""
    up, down = [], []
    for name, power in zip(("m", "rad", "s", "N"), dimension):
        if power:
            (up if power > 0 else down).append(name + (f"^{abs(power)}" if abs(power) > 1
                                                       else ""))
    text = "*".join(up) or "1"
    return text + ("/" + "*".join(down) if down else "") if up or down else ""


def unit_dimension(unit: ast.Name | None) -> Dimension | None:
    """The dimension of a written unit; ``None`` for one the language does not know."""
    if unit is None:
        return NONE
    known = lookup(unit.text)
    return None if known is None else NAMED[known.dimension]


def declared_variables(ctx: CheckContext, machine: ast.Machine,
                       visible: dict[str, VarInfo]) -> dict[str, VarInfo]:
    """``visible`` with the vars ``machine`` declares, each checked: its kind, its name
    (not another var's, constant's, task's or constraint's) and its first value."""
    found = dict(visible)
    own: dict[str, ast.VarDecl] = {}
    for decl in machine.variables:
        name = decl.name.text
        kind = KINDS.get(decl.kind.text)
        if kind is None:
            ctx.unknown("unknown-kind", "kind", decl.kind, KINDS,
                        "a var holds one of: " + ", ".join(KINDS))
        first = own.get(name) or _other_declaration(ctx, name)
        if first is not None:
            ctx.error("duplicate-name", f"'{name}' is already declared", decl.name.span,
                      f"first declared at {ctx.where(first.span)}")
            continue
        own[name] = decl
        if kind is None or ctx.measure_name(decl.name, "var"):
            continue
        typed = Typed(kind[0], kind[1], decl.kind.text == "count")
        if decl.value is not None:
            given = _action_value(ctx, decl.value, found)
            fits(ctx, given, typed, decl.value, f"the first value of '{name}'")
        found[name] = VarInfo(decl, typed)
    return found


def _other_declaration(ctx: CheckContext, name: str):
    """A constant, task or constraint already named ``name``."""
    return (ctx.constants.get(name) or ctx.symbols.tasks.get(name)
            or ctx.symbols.constraints.get(name))


def check_set_var(ctx: CheckContext, action: ast.SetVar) -> None:
    """``NAME = EXPRESSION``: a known var, a value of its dimension and size."""
    info = ctx.variables.get(action.name.text)
    given = _action_value(ctx, action.value, ctx.variables)
    if info is None:
        if action.name.text in ctx.generic:
            return
        extra = ("a constant cannot change: declare a var instead, var NAME: KIND = VALUE"
                 if action.name.text in ctx.constants else
                 "declare it: var NAME: KIND = VALUE")
        ctx.unknown("unknown-var", "var", action.name, ctx.variables, extra)
        return
    fits(ctx, given, info.typed, action.value, f"'{action.name.text}'")


def _action_value(ctx: CheckContext, node, visible) -> Typed | None:
    """An expression an action computes: ``elapsed`` belongs to clauses."""
    from .rewrite import rebuild

    found = []
    rebuild(node, lambda child: found.append(child) or child
            if isinstance(child, ast.Elapsed) else child)
    for elapsed in found:
        ctx.error("wrong-condition", "'elapsed' is read in a clause: it counts from the "
                  "entry of the state that owns the clause", elapsed.span,
                  "keep the time instead: var since: duration = 0 s, since = time, "
                  "then time - since")
    return None if found else expression(ctx, node, visible)


def fits(ctx: CheckContext, given: Typed | None, wanted: Typed, node, what: str) -> bool:
    """Whether a value fits a var (reported when it does not)."""
    if given is None:
        return False
    if given.dimension != wanted.dimension or given.size != wanted.size:
        ctx.error("wrong-dimension", f"{what} holds {describe(wanted.dimension, wanted.size)}"
                  f", not {describe(given.dimension, given.size)}", node.span,
                  _dimension_hint(wanted))
        return False
    if wanted.whole and not given.whole:
        ctx.error("wrong-value", f"{what} is a count: it holds whole numbers", node.span,
                  "add or subtract whole numbers: parts_done = parts_done + 1")
        return False
    return True


def _dimension_hint(wanted: Typed) -> str:
    named = next((n for n, d in NAMED.items() if d == wanted.dimension), None)
    if named in (None, DIMENSIONLESS):
        return "combine values whose units give this one"
    return f"give it a value in {SI_SYMBOL[named]} (or another unit of a {named})"


def expression(ctx: CheckContext, node, visible: dict[str, VarInfo]) -> Typed | None:
    """What ``node`` gives; ``None`` after reporting what is wrong in it."""
    if isinstance(node, ast.Quantity):
        dimension = unit_dimension(node.unit)
        if dimension is None:
            ctx.unknown("unknown-unit", "unit", node.unit, [], "units: m, cm, mm, rad, deg, "
                        "s, ms, N, Nm, m/s, rad/s...")
            return None
        return Typed(dimension, 1, node.unit is None and float(node.value).is_integer())
    if isinstance(node, ast.Negative):
        inner = expression(ctx, node.operand, visible)
        return inner
    if isinstance(node, ast.Binary):
        return _binary(ctx, node, visible)
    if isinstance(node, ast.Variable):
        return variable(ctx, node.name, visible)
    if isinstance(node, ast.Reference):
        return variable(ctx, node.name, visible)
    if isinstance(node, ast.Vector):
        return _vector(ctx, node)
    if isinstance(node, (ast.Member, ast.Distance, ast.Elapsed, ast.Time, ast.Wrench)):
        return measure(ctx, node)
    ctx.error("wrong-value", "this value is not a number: it cannot be computed with",
              node.span, "an expression combines numbers with units, vars, constants that "
              "hold a number and measures")
    return None


def _binary(ctx: CheckContext, node: ast.Binary, visible) -> Typed | None:
    left = expression(ctx, node.left, visible)
    right = expression(ctx, node.right, visible)
    if left is None or right is None:
        return None
    if node.operator in "+-":
        if left.dimension != right.dimension or left.size != right.size:
            ctx.error("wrong-dimension", f"'{node.operator}' needs two values of one "
                      f"dimension, not {describe(left.dimension, left.size)} and "
                      f"{describe(right.dimension, right.size)}", node.span,
                      "convert one side, or compare like with like")
            return None
        return Typed(left.dimension, left.size, left.whole and right.whole)
    if left.size == 3 and right.size == 3:
        ctx.error("wrong-value", f"'{node.operator}' multiplies or divides by a number, not "
                  "a 3-vector", node.span, "take one component: BODY.position.z")
        return None
    if node.operator == "/" and _zero(node.right):
        ctx.error("wrong-value", "division by zero: the divisor is 0", node.right.span,
                  "divide by a value that is never 0")
        return None
    sign = 1 if node.operator == "*" else -1
    dimension = tuple(a + sign * b for a, b in zip(left.dimension, right.dimension))
    if right.size == 3 and node.operator == "/":
        ctx.error("wrong-value", "a number cannot be divided by a 3-vector", node.span)
        return None
    return Typed(dimension, max(left.size, right.size),
                 node.operator == "*" and left.whole and right.whole)


def _zero(node) -> bool:
    """Whether ``node`` is a number written 0, or a vector with a component written 0."""
    while isinstance(node, ast.Negative):
        node = node.operand
    if isinstance(node, ast.Quantity):
        return float(node.value) == 0
    return isinstance(node, ast.Vector) and any(
        isinstance(value, (int, float)) and value == 0 for value in node.values)


def _vector(ctx: CheckContext, node: ast.Vector) -> Typed | None:
    if len(node.values) != 3:
        ctx.error("wrong-length", f"a vector value has {len(node.values)} values, expected 3",
                  node.span, "write three values: [x, y, z] m")
        return None
    dimension = unit_dimension(node.unit)
    return None if dimension is None else Typed(dimension, 3)


def variable(ctx: CheckContext, name: ast.Name, visible: dict[str, VarInfo]) -> Typed | None:
    """A var's value (a constant is substituted before: a name left is a var)."""
    info = visible.get(name.text)
    if info is not None:
        return info.typed
    if name.text in ctx.generic:
        return None
    ctx.unknown("unknown-name", "var or constant", name, [*visible, *ctx.numbers],
                "declare it: var NAME: KIND = VALUE, or let NAME = VALUE")
    return None


def measure(ctx: CheckContext, node) -> Typed | None:
    """A measure read in an expression: its dimension (see :mod:`.conditions`)."""
    from .conditions import measure_dimensions

    if isinstance(node, ast.Member) and _is_position(ctx, node):
        return body_position(ctx, node)
    dimensions = measure_dimensions(ctx, node)
    if dimensions is None:
        return None
    if len(set(dimensions)) > 1:
        ctx.error("wrong-dimension", "this measure mixes dimensions: it cannot be computed "
                  "with", node.span, "read one part: X.position_error or X.orientation_error")
        return None
    visits = isinstance(node, ast.Member) and node.field.text == "visits"
    return Typed(NAMED[dimensions[0]], 1, visits)


def _is_position(ctx: CheckContext, member: ast.Member) -> bool:
    field = member.region.text if member.region is not None else member.field.text
    return field == "position" and ctx.world.has_body(member.owner.text) \
        and member.owner.text not in ctx.symbols.tasks


def body_position(ctx: CheckContext, member: ast.Member) -> Typed | None:
    """``BODY.position`` (a 3-vector [m]) or ``BODY.position.x|y|z`` [m]."""
    if member.region is None:
        return Typed(NAMED[LENGTH], 3)
    if member.field.text not in AXES:
        ctx.unknown("unknown-field", "axis", member.field, AXES,
                    "a position has x, y and z", where=" of a position")
        return None
    return Typed(NAMED[LENGTH], 1)


def check_log(ctx: CheckContext, log: ast.Log) -> None:
    """Every ``{NAME}`` of a log text names a var (those of constants were written in
    when they were bound)."""
    for match in PLACEHOLDER.finditer(log.text):
        name = match.group(1).strip()
        if name in ctx.variables or name in ctx.generic:
            continue
        span = log.span
        column = span.column + len('log "') + match.start()
        at = type(span)(span.line, column, span.line, column + len(match.group(0)), span.file)
        ctx.error("unknown-name", f"unknown var or constant '{name}' in the log text", at,
                  did_you_mean(name, [*ctx.variables, *ctx.constants])
                  or "write {NAME} with the name of a var or a constant")


def check_reads(ctx: CheckContext, machine: ast.Machine) -> None:
    """Warn where a var without a first value may be read before any assignment: along
    some path of clauses from the start, no state or clause assigned it."""
    late = {v.name.text for m in _machines(machine) for v in m.variables if v.value is None}
    if late:
        _flow(ctx, machine, frozenset(), late)


def _machines(machine: ast.Machine):
    yield machine
    for state in machine.states:
        for region in state.regions:
            if region.machine is not None:
                yield from _machines(region.machine)


def _flow(ctx: CheckContext, machine: ast.Machine, entry: frozenset, late: set) -> None:
    """Every read in ``machine``, entered with ``entry`` surely assigned."""
    states = {s.name.text: s for s in machine.states}
    if not states:
        return
    start = machine.start.state.text if machine.start else next(iter(states))
    every = frozenset(late)
    entries = {name: (entry if name == start else every) for name in states}
    changed = True
    while changed:
        changed = False
        incoming: dict[str, list] = {name: [] for name in states}
        for name, state in states.items():
            out = entries[name] | _assigned_in(state, clauses=False)
            for transition in (*state.transitions, *machine.guards):
                if transition.target.text in incoming:
                    incoming[transition.target.text].append(
                        out | _assigned(transition.actions))
        for name in states:
            if name == start:
                continue
            new = frozenset.intersection(*incoming[name]) if incoming[name] else every
            if new != entries[name]:
                entries[name], changed = new, True
    for name, state in states.items():
        _reads_of_state(ctx, state, entries[name], late)
    for guard in machine.guards:
        _warn(ctx, _reads(guard.condition), entry, late)
        _warn_actions(ctx, guard.actions, entry, late)


def _reads_of_state(ctx: CheckContext, state: ast.StateDecl, entry: frozenset,
                    late: set) -> None:
    enter = state.block("enter")
    entered = entry | _assigned(enter.actions if enter else ())
    for block in state.blocks:
        _warn_actions(ctx, block.actions, entry if block is enter else entered, late)
    during = state.block("during")
    settled = entered | _assigned(during.actions if during else ())
    for transition in state.transitions:
        _warn(ctx, _reads(transition.condition), settled, late)
        _warn_actions(ctx, transition.actions, settled, late)
    for region in state.regions:
        if region.machine is not None:
            _flow(ctx, region.machine, entered, late)


def _warn_actions(ctx: CheckContext, actions, assigned: frozenset, late: set) -> None:
    """Actions in order: each reads what the ones before it assigned."""
    for action in actions:
        _warn(ctx, _reads(action), assigned, late)
        assigned = assigned | _assigned((action,))


def _warn(ctx: CheckContext, reads: list, assigned: frozenset, late: set) -> None:
    for name in reads:
        if name.text in late and name.text not in assigned:
            ctx.warning("read-before-assignment", f"'{name.text}' may be read before any "
                        "assignment", name.span, "give it a first value in its declaration "
                        "(var NAME: KIND = VALUE), or assign it in a state before this one")


def _assigned(actions) -> frozenset:
    return frozenset(a.name.text for a in actions if isinstance(a, ast.SetVar))


def _assigned_in(state: ast.StateDecl, clauses: bool = True) -> frozenset:
    """What a state assigns in its blocks, its clauses' actions (unless ``clauses`` is
    false: leaving by one clause, the others' actions have not run) and its machines."""
    found = set()
    for part in state.parts:
        if clauses or not isinstance(part, ast.Transition):
            found |= _assigned(part.actions)
    for region in state.regions:
        for machine in (() if region.machine is None else _machines(region.machine)):
            for item in machine.items:
                if isinstance(item, ast.Transition):
                    found |= _assigned(item.actions)
                elif isinstance(item, ast.StateDecl):
                    found |= _assigned_in(item)
    return frozenset(found)


def _reads(node) -> list[ast.Name]:
    """The names a node reads as values (vars, in order)."""
    found = []

    def visit(child):
        if isinstance(child, ast.Variable):
            found.append(child.name)
        elif isinstance(child, ast.NameElement):
            found.append(child.name)
        elif isinstance(child, ast.Comparison) and isinstance(child.quantity, ast.Reference):
            found.append(child.quantity.name)
        elif isinstance(child, ast.Log):
            found.extend(ast.Name(m.group(1).strip(), span=child.span)
                         for m in PLACEHOLDER.finditer(child.text))
        return child

    from .rewrite import rebuild

    rebuild(node, visit)
    return found
