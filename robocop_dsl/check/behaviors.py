"""Behaviours: typed parameters, and the arguments an instance binds to them.

A parameter is a name of something declared (``task``, ``constraint``, ``body``,
``joint_group``, ``event``), a quantity of one dimension (``length``, ``angle``,
``duration``, ``linear_velocity``, ``angular_velocity``, ``linear_acceleration``,
``angular_acceleration``, ``number``) or a ``target`` (anything a task target accepts,
checked where it is used). Arguments are positional, then named; defaults fill in.
"""

from __future__ import annotations

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


def check_behavior_declarations(ctx: CheckContext, behaviors: dict[str, ast.BehaviorDecl],
                                lets: dict[str, Binding]) -> None:
    """Parameter kinds, repeated parameters and defaults of every behaviour."""
    for behavior in behaviors.values():
        seen: dict[str, ast.BehaviorParam] = {}
        for parameter in behavior.parameters:
            if parameter.name.text in seen:
                ctx.error("duplicate-name", f"parameter '{parameter.name.text}' is already "
                          f"declared in behavior '{behavior.name.text}'", parameter.name.span,
                          f"first declared at {ctx.where(seen[parameter.name.text].span)}")
            seen.setdefault(parameter.name.text, parameter)
            if parameter.kind.text not in KINDS:
                ctx.unknown("unknown-parameter-kind", "parameter kind", parameter.kind, KINDS,
                            "kinds: " + ", ".join(KINDS))
            elif parameter.default is not None:
                _check_argument(ctx, parameter, substitute(ctx, parameter.default, lets))


def instance_text(instance: ast.Instance) -> str:
    """``approach(left_tool, pickup_point, height = 5 cm)``."""
    arguments = [(f"{a.name.text} = " if a.name else "") + format_value(a.value)
                 for a in instance.arguments]
    return f"{instance.behavior.text}({', '.join(arguments)})"


def bind_arguments(ctx: CheckContext, instance: ast.Instance, behavior: ast.BehaviorDecl,
                   lets: dict[str, Binding]) -> dict[str, Binding] | None:
    """The bindings of an instance's behaviour (constants, then its parameters); ``None``
    after reporting arguments that do not fit."""
    parameters = {p.name.text: p for p in behavior.parameters}
    given: dict[str, ast.Argument] = {}
    ok = True
    for index, argument in enumerate(instance.arguments):
        if argument.name is None:
            if any(a.name is not None for a in instance.arguments[:index]):
                ctx.error("wrong-arguments", "a positional argument after a named one",
                          argument.span, "write the positional arguments first")
                ok = False
                continue
            if index >= len(behavior.parameters):
                ctx.error("extra-argument", f"{behavior.name.text} takes "
                          f"{len(behavior.parameters)} argument(s), this is one too many",
                          argument.span, _signature(behavior))
                ok = False
                continue
            name = behavior.parameters[index].name.text
        else:
            name = argument.name.text
            if name not in parameters:
                ctx.unknown("unknown-argument", f"argument of {behavior.name.text}",
                            argument.name, parameters, _signature(behavior))
                ok = False
                continue
        if name in given:
            ctx.error("duplicate-argument", f"argument '{name}' is given twice",
                      argument.span, f"the first is at {ctx.where(given[name].span)}")
            ok = False
            continue
        given[name] = argument
    bindings = dict(lets)
    for name, parameter in parameters.items():
        if name in given:
            value = given[name].value
        elif parameter.default is not None:
            value = substitute(ctx, parameter.default, lets)
        else:
            ctx.error("missing-argument", f"{behavior.name.text} needs the argument "
                      f"'{name}' ({parameter.kind.text})", instance.behavior.span,
                      _signature(behavior))
            ok = False
            continue
        bound = _check_argument(ctx, parameter, value)
        if bound is None:
            ok = False
            continue
        bindings[name] = Binding(name, bound, parameter.span)
    return bindings if ok else None


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
                      f"{kind.replace('_', ' ')}", value.span)
            return None
        return value.name if _known_name(ctx, kind, value.name, what) else None
    if kind in DIMENSION_KINDS:
        if isinstance(value, ast.Reference) and value.name.text in ctx.generic:
            return value
        if not isinstance(value, ast.Quantity):
            ctx.error("wrong-argument-kind", f"{what} expects one number", value.span,
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
                  f"expects a {kind.replace('_', ' ')}", name.span)
        return False
    candidates = {"task": ctx.symbols.tasks, "constraint": ctx.symbols.constraints,
                  "body": ctx.world.body_names(), "joint_group": ctx.world.joint_names(),
                  "event": ctx.symbols.events}[kind]
    if kind in ("body", "joint_group") and not ctx.world.known:
        return True
    ctx.error(f"unknown-{kind.replace('_', '-')}" if kind != "constraint" else "unknown-task",
              f"unknown {kind.replace('_', ' ')} '{text}'", name.span,
              did_you_mean(text, candidates))
    return False


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
                     lets: dict[str, Binding]):
    """Bindings to check a behaviour that nothing instantiates: parameters with a default
    take it, the others stand for any value of their kind (``ctx.generic``)."""
    bindings, generic = dict(lets), set()
    for parameter in behavior.parameters:
        if parameter.default is not None:
            value = substitute(ctx, parameter.default, lets)
            if parameter.kind.text in NAME_KINDS and isinstance(value, ast.Reference):
                value = value.name
            bindings[parameter.name.text] = Binding(parameter.name.text, value, parameter.span)
        else:
            generic.add(parameter.name.text)
            bindings.pop(parameter.name.text, None)
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
