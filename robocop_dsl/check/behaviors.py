"""Behaviours: typed parameters, and the arguments an instance binds to them.

A parameter is a name of something declared (``task``, ``constraint``, ``body``,
``joint_group``, ``event``), a quantity of one dimension (``length``, ``angle``,
``duration``, ``linear_velocity``, ``angular_velocity``, ``linear_acceleration``,
``angular_acceleration``, ``number``) or a ``target`` (anything a task target accepts,
checked where it is used). Arguments are positional, then named; defaults fill in.
"""

from __future__ import annotations

import dataclasses

import networkx as nx

from ..diagnostics import did_you_mean
from ..lang import ast
from ..lang.formatter import format_value
from ..lang.units import (ANGLE, ANGULAR_ACCELERATION, ANGULAR_VELOCITY, DIMENSIONLESS,
                          LENGTH, LINEAR_ACCELERATION, LINEAR_VELOCITY, SI_SYMBOL, TIME)
from .bindings import Binding, substitute
from .context import CheckContext
from .values import check_quantity

NAME_KINDS = ("task", "constraint", "body", "joint_group", "event")
DIMENSION_KINDS = {"length": LENGTH, "angle": ANGLE, "duration": TIME,
                   "linear_velocity": LINEAR_VELOCITY, "angular_velocity": ANGULAR_VELOCITY,
                   "linear_acceleration": LINEAR_ACCELERATION,
                   "angular_acceleration": ANGULAR_ACCELERATION, "number": DIMENSIONLESS}
TARGET = "target"
KINDS = (*NAME_KINDS, *DIMENSION_KINDS, TARGET)
WORDS = ("current", "world", "none")


def check_behavior_declarations(ctx: CheckContext, behaviors: dict[str, ast.BehaviorDecl],
                                lets: dict[str, Binding]) -> set[tuple[str, str]]:
    """Parameter kinds, repeated parameters and defaults of every behaviour; return the
    ``(behaviour, parameter)`` pairs whose default does not fit."""
    bad = set()
    for behavior in behaviors.values():
        seen: dict[str, ast.BehaviorParam] = {}
        for parameter in behavior.parameters:
            if parameter.name.text in seen:
                ctx.error("duplicate-name", f"parameter '{parameter.name.text}' is already "
                          f"declared in behavior '{behavior.name.text}'", parameter.name.span,
                          f"first declared as '{parameter.name.text}: "
                          f"{seen[parameter.name.text].kind.text}'")
            seen.setdefault(parameter.name.text, parameter)
            if ctx.measure_name(parameter.name, "parameter"):
                bad.add((behavior.name.text, parameter.name.text))
            elif parameter.kind.text not in KINDS:
                ctx.unknown("unknown-parameter-kind", "parameter kind", parameter.kind, KINDS,
                            "kinds: " + ", ".join(KINDS))
                bad.add((behavior.name.text, parameter.name.text))
            elif parameter.default is not None and _check_argument(
                    ctx, parameter, substitute(ctx, parameter.default, lets)) is None:
                bad.add((behavior.name.text, parameter.name.text))
    return bad


def instance_text(instance: ast.Instance) -> str:
    """``approach(left_tool, pickup_point, height = 5 cm)``."""
    return f"{instance.behavior.text}({', '.join(map(_argument_text, instance.arguments))})"


def _argument_text(argument: ast.Argument) -> str:
    return (f"{argument.name.text} = " if argument.name else "") + format_value(argument.value)


def bind_arguments(ctx: CheckContext, instance: ast.Instance, behavior: ast.BehaviorDecl,
                   lets: dict[str, Binding]) -> dict[str, Binding] | None:
    """The bindings of an instance's behaviour (constants, then its parameters); ``None``
    after reporting arguments that do not fit."""
    parameters: dict[str, ast.BehaviorParam] = {}
    for parameter in behavior.parameters:
        parameters.setdefault(parameter.name.text, parameter)
    given: dict[str, ast.Argument] = {}
    ok = True
    for index, argument in enumerate(instance.arguments):
        if argument.name is None:
            if index >= len(behavior.parameters):
                continue
            if any(a.name is not None for a in instance.arguments[:index]):
                ctx.error("wrong-arguments", "a positional argument after a named one",
                          argument.span, "write the positional arguments first")
                ok = False
            name = behavior.parameters[index].name.text
        else:
            name = argument.name.text
            if name not in parameters:
                ctx.unknown("unknown-argument", "argument", argument.name, parameters,
                            _signature(behavior), where=f" of {behavior.name.text}")
                ok = False
                continue
        if name in given:
            ctx.error("duplicate-argument", f"argument '{name}' is given twice",
                      argument.span, f"it is first given as '{_argument_text(given[name])}'")
            ok = False
            continue
        given[name] = argument
    ok = _check_extra(ctx, instance, behavior) and ok
    bindings = dict(lets)
    missing = []
    for name, parameter in parameters.items():
        if name in given:
            value = given[name].value
        elif parameter.default is not None:
            value = substitute(ctx, parameter.default, lets)
        else:
            missing.append(f"'{name}' ({parameter.kind.text})")
            continue
        bound = _check_argument(ctx, parameter, value)
        if bound is None:
            ok = False
            continue
        bindings[name] = Binding(name, bound, parameter.span)
    if missing:
        ctx.error("missing-argument", f"{behavior.name.text} needs the argument"
                  f"{'s' if len(missing) > 1 else ''} {', '.join(missing)}",
                  instance.behavior.span, _signature(behavior))
    return bindings if ok and not missing else None


def _check_extra(ctx: CheckContext, instance: ast.Instance,
                 behavior: ast.BehaviorDecl) -> bool:
    """Report positional arguments beyond the behaviour's parameters."""
    count = len(behavior.parameters)
    extra = [a for a in instance.arguments[count:] if a.name is None]
    if not extra:
        return True
    positional = sum(a.name is None for a in instance.arguments)
    span = dataclasses.replace(extra[0].span, end_line=extra[-1].span.end_line,
                               end_column=extra[-1].span.end_column)
    ctx.error("extra-argument", f"{behavior.name.text} takes {count} argument"
              f"{'' if count == 1 else 's'}, not {positional}", span, _signature(behavior))
    return False


def _signature(behavior: ast.BehaviorDecl) -> str:
    parameters = ", ".join(f"{p.name.text}: {p.kind.text}" + (" = ..." if p.default else "")
                           for p in behavior.parameters)
    return f"{behavior.name.text}({parameters})"


def _check_argument(ctx: CheckContext, parameter: ast.BehaviorParam, value):
    """The value bound to ``parameter`` (an :class:`ast.Name` for name kinds), ``None``
    after reporting a value of the wrong kind or dimension."""
    kind = parameter.kind.text
    what = f"parameter '{parameter.name.text}' ({kind})"
    if kind in NAME_KINDS:
        if not isinstance(value, ast.Reference):
            ctx.error("wrong-argument-kind", f"{what} expects the name of a "
                      f"{kind.replace('_', ' ')}", value.span, _names_hint(ctx, kind))
            return None
        return value.name if _known_name(ctx, kind, value.name, what) else None
    if kind in DIMENSION_KINDS:
        if ctx.opaque(value):
            return value
        if isinstance(value, ast.Reference) and value.name.text not in WORDS \
                and kind_of_name(ctx, value.name.text) is None:
            ctx.unknown("unknown-name", "constant", value.name, ctx.numbers,
                        f"{what} expects one number: {_example(kind)}")
            return None
        if not isinstance(value, ast.Quantity):
            found = kind_of_name(ctx, value.name.text) \
                if isinstance(value, ast.Reference) else None
            shown = f"'{value.name.text}' is a {found.replace('_', ' ')}: " if found else ""
            ctx.error("wrong-argument-kind", f"{shown}{what} expects one number", value.span,
                      _example(kind))
            return None
        return value if check_quantity(ctx, value, (DIMENSION_KINDS[kind],), what) \
            is not None else None
    return value


def _example(kind: str) -> str:
    symbol = SI_SYMBOL[DIMENSION_KINDS[kind]]
    return f"for example 1 {symbol}" if symbol else "for example 1"


def _known_name(ctx: CheckContext, kind: str, name: ast.Name, what: str) -> bool:
    text = name.text
    if text in ctx.generic:
        return True
    found = kind_of_name(ctx, text)
    if found == kind:
        return True
    if found is not None:
        ctx.error("wrong-argument-kind", f"'{text}' is a {found.replace('_', ' ')}: {what} "
                  f"expects a {kind.replace('_', ' ')}", name.span, _names_hint(ctx, kind))
        return False
    if kind in ("body", "joint_group") and not ctx.world.known:
        return True
    ctx.error(f"unknown-{kind.replace('_', '-')}" if kind != "constraint" else "unknown-task",
              f"unknown {kind.replace('_', ' ')} '{text}'", name.span,
              did_you_mean(text, _names(ctx, kind)) or _names_hint(ctx, kind))
    return False


def _names(ctx: CheckContext, kind: str):
    return {"task": ctx.symbols.tasks, "constraint": ctx.symbols.constraints,
            "body": ctx.world.body_names(), "joint_group": ctx.world.joint_names(),
            "event": ctx.symbols.events}[kind]


def _names_hint(ctx: CheckContext, kind: str) -> str:
    """``tasks: arms, left_tool`` (the first few names of a kind)."""
    names = sorted(_names(ctx, kind))
    shown = ", ".join(names[:6]) + (", ..." if len(names) > 6 else "")
    return f"{kind.replace('_', ' ')}s: {shown}" if names else \
        f"the mission declares no {kind.replace('_', ' ')}"


def kind_of_name(ctx: CheckContext, text: str) -> str | None:
    """What a declared name is: task, constraint, event, body or joint_group."""
    if text in ctx.symbols.tasks:
        return "task"
    if text in ctx.symbols.constraints:
        return "constraint"
    if text in ctx.symbols.events:
        return "event"
    if ctx.world.known and ctx.world.world.has_body(text):
        return "body"
    if ctx.world.known and ctx.world.joints(text) is not None:
        return "joint_group"
    return None


def generic_bindings(ctx: CheckContext, behavior: ast.BehaviorDecl,
                     lets: dict[str, Binding], bad: set[tuple[str, str]]):
    """Bindings to check a behaviour that no instance exposes: parameters with a default
    that fits take it, the others stand for any value of their kind (the names
    returned, for ``ctx.generic``)."""
    bindings, generic = dict(lets), set()
    for parameter in behavior.parameters:
        name = parameter.name.text
        if parameter.default is not None and (behavior.name.text, name) not in bad:
            value = substitute(ctx, parameter.default, lets)
            if parameter.kind.text in NAME_KINDS and isinstance(value, ast.Reference):
                value = value.name
            bindings[name] = Binding(name, value, parameter.span)
        else:
            generic.add(name)
            bindings.pop(name, None)
    return bindings, frozenset(generic)


def instantiated(machine: ast.Machine) -> list[ast.Instance]:
    """The behaviour instances written in a machine, at any depth."""
    found = []
    for state in machine.states:
        if state.instance is not None:
            found.append(state.instance)
        for region in state.regions:
            if region.instance is not None:
                found.append(region.instance)
            if region.machine is not None:
                found += instantiated(region.machine)
    return found


def check_recursion(ctx: CheckContext, behaviors: dict[str, ast.BehaviorDecl]) -> set[str]:
    """Report behaviours that instantiate themselves, directly or through others; return
    their names (they are not expanded)."""
    graph = nx.DiGraph()
    for name, behavior in behaviors.items():
        graph.add_node(name)
        for instance in instantiated(behavior.machine):
            if instance.behavior.text in behaviors:
                graph.add_edge(name, instance.behavior.text, span=instance.behavior.span)
    recursive = set()
    for component in nx.strongly_connected_components(graph):
        name = min(component)
        if len(component) == 1 and not graph.has_edge(name, name):
            continue
        recursive |= component
        edges = nx.find_cycle(graph.subgraph(component), source=name)
        span = graph.edges[edges[-1]]["span"]
        others = [source for source, _ in edges[1:]]
        through = (" through " + ", ".join(others)) if others else ""
        ctx.error("recursive-behavior", f"behavior '{name}' instantiates itself{through}",
                  span, "a behaviour may instantiate other behaviours, never itself: "
                  "repeat with a clause that re-enters the state instead (S.visits)")
    return recursive
