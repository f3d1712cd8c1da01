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

from ..diagnostics import Diagnostic
from ..lang import ast
from .behaviors import (bind_arguments, check_behavior_declarations, check_recursion,
                        generic_bindings, instance_text, instantiated)
from .bindings import Binding, substitute
from .constants import declared_constants
from .context import CheckContext


MAX_INSTANCE_DEPTH = 24
"""How deep behaviour instances may nest (each inside the previous one's machine)."""


def declared_behaviors(ctx: CheckContext, mission: ast.Mission) -> dict[str, ast.BehaviorDecl]:
    """The behaviours by name, the first of each; one with no state is reported."""
    behaviors: dict[str, ast.BehaviorDecl] = {}
    for behavior in mission.behaviors:
        first = behaviors.get(behavior.name.text)
        if first is not None:
            ctx.error("duplicate-name", f"behavior '{behavior.name.text}' is already declared",
                      behavior.name.span, f"first declared at {ctx.where(first.span)}")
            continue
        behaviors[behavior.name.text] = behavior
        if not behavior.machine.states:
            ctx.error("missing-declaration", f"behavior '{behavior.name.text}' declares no "
                      "state", behavior.name.span, "add: state NAME { ... } and a final: "
                      "its outcome")
    return behaviors


class Expander:
    """Expands a mission's machine against its constants and behaviours.

    ``exposed`` names the behaviours that some instance expanded (their body was
    checked with its arguments bound)."""

    def __init__(self, ctx: CheckContext, mission: ast.Mission):
        self.ctx = ctx
        self.lets = declared_constants(ctx, mission)
        ctx.all_variables = {v.name.text for machine in
                             (mission.machine, *(b.machine for b in mission.behaviors))
                             for v in machine.variables}
        ctx.numbers = [n for n, b in self.lets.items() if isinstance(b.value, ast.Quantity)]
        ctx.vectors = [n for n, b in self.lets.items() if isinstance(b.value, ast.Vector)]
        self.base = ctx.generic
        self.behaviors = declared_behaviors(ctx, mission)
        self.bad_defaults = check_behavior_declarations(ctx, self.behaviors, self.lets)
        self.recursive = check_recursion(ctx, self.behaviors)
        self.exposed: set[str] = set()
        self.expansions: dict[tuple, tuple[ast.Machine, list[Diagnostic], int]] = {}

    def mission(self, mission: ast.Mission) -> ast.Mission:
        """``mission`` with constants bound in its declarations and its machine expanded."""
        items = []
        for item in mission.items:
            if isinstance(item, (ast.TaskDecl, ast.ConstraintDecl, ast.Transition,
                                 ast.VarDecl)):
                item = substitute(self.ctx, item, self.lets)
            elif isinstance(item, ast.StateDecl):
                item = self.state(item, self.lets)
            items.append(item)
        return dataclasses.replace(mission, items=tuple(items))

    def unused_behaviors(self) -> list[tuple[str, ast.Machine, frozenset[str]]]:
        """The behaviours that no instance exposes, each expanded with generic bindings
        (see :func:`generic_bindings`): its name, its machine and the names that stand
        for any value while it is checked. One that only such a behaviour instantiates
        is exposed through it; a recursive one is checked with its recursive instances
        left unexpanded."""
        found = []
        callers = {name: {i.behavior.text for i in instantiated(b.machine)}
                   for name, b in self.behaviors.items()}
        while True:
            checked = self.exposed | {f[0] for f in found}
            pending = [n for n in self.behaviors if n not in checked]
            roots = [n for n in pending if not any(
                n in callers[c] for c in pending if c not in self.recursive)]
            if not roots:
                return found
            name = roots[0]
            behavior = self.behaviors[name]
            bindings, generic = generic_bindings(self.ctx, behavior, self.lets,
                                                 self.bad_defaults)
            self.ctx.generic = self.base | generic
            found.append((name, self.machine(behavior.machine, bindings, (name,)),
                          self.ctx.generic))
            self.ctx.generic = self.base

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
        if len(stack) >= MAX_INSTANCE_DEPTH:
            self.ctx.error("nesting-too-deep", f"behaviour instances nest more than "
                           f"{MAX_INSTANCE_DEPTH} deep here", instance.span,
                           "flatten the chain: instantiate behaviours side by side in one "
                           "machine rather than each inside the next")
            return None
        bindings = bind_arguments(self.ctx, instance, behavior, self.lets)
        if bindings is None:
            return None
        self.exposed.add(name)
        notes = self.ctx.notes
        self.ctx.notes = (instance_note(self.ctx, instance), *notes)
        try:
            return self.bound(name, bindings, (*stack, name))
        finally:
            self.ctx.notes = notes

    def bound(self, name: str, bindings: dict[str, Binding],
              stack: tuple[str, ...]) -> ast.Machine:
        """Behaviour ``name``'s machine expanded with ``bindings``, made once per set of
        bound values: a substituted value takes the span of the name it replaces, so
        instances that bind equal values get equal machines and the same problems, which
        are reported again with the notes of each."""
        key = (name, stack, self.ctx.generic, *(
            (parameter, repr(binding.value), binding.span) for parameter, binding
            in bindings.items() if binding is not self.lets.get(parameter)))
        known = self.expansions.get(key)
        outer = self.ctx.notes
        if known is None:
            start = len(self.ctx.diagnostics)
            machine = self.machine(self.behaviors[name].machine, bindings, stack)
            known = (machine, self.ctx.diagnostics[start:], len(outer))
            self.expansions[key] = known
            return machine
        machine, problems, kept = known
        self.ctx.diagnostics += [dataclasses.replace(
            d, notes=d.notes[:len(d.notes) - kept] + outer) for d in problems]
        return machine


def instance_note(ctx: CheckContext, instance: ast.Instance) -> str:
    """``in approach(left_tool, pickup_point) at two_parts.mission:22:12``, written once
    per instance node (kept in ``ctx.instance_notes`` with the node, by its identity)."""
    known = ctx.instance_notes.get(id(instance))
    if known is None:
        known = (instance, f"in {instance_text(instance)} at "
                           f"{instance.span.location(ctx.source_of(instance.span).path)}")
        ctx.instance_notes[id(instance)] = known
    return known[1]
