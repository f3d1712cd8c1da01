"""Bind constants and expand behaviour instances: the tree every later check and the
compiler read.

Constants are substituted everywhere. Each ``state S: B(ARGS)`` and ``region R: B(ARGS)``
gets B's machine with B's parameters bound to the arguments (evaluated where the
instance is written), as its region's ``machine``; instances inside it are expanded in
turn. Scoping is lexical: a behaviour's body sees the constants and its own parameters.
An instance whose arguments do not fit keeps no machine (its region's ``machine`` is
``None``), so that its problems are reported once, at the instance.
"""

from __future__ import annotations

import dataclasses

from ..lang import ast
from .behaviors import (bind_arguments, check_behavior_declarations, check_recursion,
                        generic_bindings, instance_text, instantiated)
from .bindings import Binding, substitute
from .context import CheckContext


def declared_constants(ctx: CheckContext, mission: ast.Mission) -> dict[str, Binding]:
    """The ``let`` constants in order, each substituted with the ones before it."""
    lets: dict[str, Binding] = {}
    for let in mission.of_type(ast.Let):
        if let.name.text in lets:
            ctx.error("duplicate-name", f"constant '{let.name.text}' is already declared",
                      let.name.span, f"first declared at {ctx.where(lets[let.name.text].span)}")
            continue
        lets[let.name.text] = Binding(let.name.text, substitute(ctx, let.value, lets), let.span)
    return lets


def declared_behaviors(ctx: CheckContext, mission: ast.Mission) -> dict[str, ast.BehaviorDecl]:
    behaviors: dict[str, ast.BehaviorDecl] = {}
    for behavior in mission.behaviors:
        first = behaviors.get(behavior.name.text)
        if first is not None:
            ctx.error("duplicate-name", f"behavior '{behavior.name.text}' is already declared",
                      behavior.name.span, f"first declared at {ctx.where(first.span)}")
            continue
        behaviors[behavior.name.text] = behavior
    return behaviors


class Expander:
    """Expands a mission's machine against its constants and behaviours."""

    def __init__(self, ctx: CheckContext, mission: ast.Mission):
        self.ctx = ctx
        self.lets = declared_constants(ctx, mission)
        self.behaviors = declared_behaviors(ctx, mission)
        check_behavior_declarations(ctx, self.behaviors, self.lets)
        self.recursive = check_recursion(ctx, self.behaviors)

    def mission(self, mission: ast.Mission) -> ast.Mission:
        """``mission`` with constants bound in its declarations and its machine expanded."""
        items = []
        for item in mission.items:
            if isinstance(item, (ast.TaskDecl, ast.ConstraintDecl)):
                item = substitute(self.ctx, item, self.lets)
            elif isinstance(item, ast.StateDecl):
                item = self.state(item, self.lets)
            elif isinstance(item, ast.Transition):
                item = substitute(self.ctx, item, self.lets)
            items.append(item)
        return dataclasses.replace(mission, items=tuple(items))

    def unused_behaviors(self, mission: ast.Mission, own: set[str]) -> list[ast.Machine]:
        """The behaviours of the checked file that nothing instantiates, expanded with
        generic bindings (see :func:`generic_bindings`), each with its parameters' names."""
        used = {i.behavior.text for i in instantiated(mission.machine)}
        for behavior in self.behaviors.values():
            used |= {i.behavior.text for i in instantiated(behavior.machine)}
        found = []
        for name, behavior in self.behaviors.items():
            if name in used or name not in own or name in self.recursive:
                continue
            bindings, generic = generic_bindings(self.ctx, behavior, self.lets)
            self.ctx.generic = generic
            found.append((self.machine(behavior.machine, bindings, (name,)), generic))
            self.ctx.generic = frozenset()
        return found

    def machine(self, machine: ast.Machine, bindings: dict[str, Binding],
                stack: tuple[str, ...]) -> ast.Machine:
        items = tuple(self.state(i, bindings, stack) if isinstance(i, ast.StateDecl)
                      else substitute(self.ctx, i, bindings) for i in machine.items)
        return dataclasses.replace(machine, items=items)

    def state(self, state: ast.StateDecl, bindings: dict[str, Binding],
              stack: tuple[str, ...] = ()) -> ast.StateDecl:
        parts = substitute(self.ctx, state.parts, bindings)
        regions = tuple(self.region(r, bindings, stack) for r in state.regions)
        if state.instance is not None:
            regions = (self.region(ast.Region(None, instance=state.instance,
                                              span=state.instance.span), bindings, stack),)
        return dataclasses.replace(state, parts=parts, regions=regions)

    def region(self, region: ast.Region, bindings: dict[str, Binding],
               stack: tuple[str, ...]) -> ast.Region:
        if region.instance is None:
            machine = region.machine or ast.Machine()
            return dataclasses.replace(region, machine=self.machine(machine, bindings, stack))
        instance = substitute(self.ctx, region.instance, bindings)
        return dataclasses.replace(region, instance=instance,
                                   machine=self.instance(instance, stack))

    def instance(self, instance: ast.Instance, stack: tuple[str, ...]) -> ast.Machine | None:
        """The machine of a behaviour instance with its arguments bound, or ``None``."""
        name = instance.behavior.text
        behavior = self.behaviors.get(name)
        if behavior is None:
            self.ctx.unknown("unknown-behavior", "behavior", instance.behavior,
                             self.behaviors, "declare it: behavior NAME(PARAMETERS) { ... }, "
                             "or import the file that does")
            return None
        if name in self.recursive or name in stack:
            return None
        bindings = bind_arguments(self.ctx, instance, behavior, self.lets)
        if bindings is None:
            return None
        notes = self.ctx.notes
        self.ctx.notes = (instance_note(self.ctx, instance), *notes)
        try:
            return self.machine(behavior.machine, bindings, (*stack, name))
        finally:
            self.ctx.notes = notes


def instance_note(ctx: CheckContext, instance: ast.Instance) -> str:
    """``in approach(left_tool, pickup_point) at two_parts.mission:22:12``."""
    return f"in {instance_text(instance)} at " \
           f"{instance.span.location(ctx.source_of(instance.span).path)}"
