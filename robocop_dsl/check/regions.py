"""Parallel regions: a task or constraint is changed by one region at most.

Changing means ``enable``, ``disable``, ``reset`` or assigning a field, in any block or
transition of a region's machine at any depth (behaviour instances included). Reading
is free.
"""

from __future__ import annotations

from ..lang import ast
from .context import CheckContext
from .expand import instance_note

_CHANGES = (ast.Enable, ast.Disable, ast.Reset)


def check_regions(ctx: CheckContext, machine: ast.Machine) -> None:
    """Report every task or constraint changed by two regions of one parallel state."""
    for state in machine.states:
        if state.parallel:
            _check_parallel(ctx, state)
        for region in state.regions:
            if region.machine is None:
                continue
            notes = ctx.notes
            if region.instance is not None:
                ctx.notes = (instance_note(ctx, region.instance), *notes)
            check_regions(ctx, region.machine)
            ctx.notes = notes


def _check_parallel(ctx: CheckContext, state: ast.StateDecl) -> None:
    owners: dict[str, tuple[str, ast.Name, tuple[str, ...]]] = {}
    outer = ctx.notes
    for region in state.regions:
        if region.machine is None or region.name is None:
            continue
        own = (instance_note(ctx, region.instance),) if region.instance else ()
        mine: dict[str, tuple[ast.Name, tuple[str, ...]]] = {}
        for name, notes in changed(ctx, region.machine):
            mine.setdefault(name.text, (name, notes + own))
        for text, (name, notes) in mine.items():
            if text not in owners:
                owners[text] = (region.name.text, name, notes)
                continue
            first_region, first, first_notes = owners[text]
            also = (f"region '{first_region}' changes it {first_notes[0]}",) \
                if first_notes else ()
            ctx.notes = (*notes, *outer, *also)
            ctx.error("region-conflict", f"'{text}' is changed by regions '{first_region}' "
                      f"({ctx.where(first.span)}) and '{region.name.text}' "
                      f"({ctx.where(name.span)}) of '{state.name.text}'", name.span,
                      "a task or constraint is changed by one region at most: change it in "
                      "one region, or in the parallel state's own blocks")
            ctx.notes = outer


def changed(ctx: CheckContext, machine: ast.Machine) -> list[tuple[ast.Name, tuple[str, ...]]]:
    """The task and constraint names a machine changes, at any depth, in source order,
    each with the notes of the behaviour instances it is in (innermost first)."""
    found = []
    for item in machine.items:
        if isinstance(item, ast.Transition):
            found += [(n, ()) for n in _changed_by(item.actions)]
        elif isinstance(item, ast.StateDecl):
            for part in item.parts:
                found += [(n, ()) for n in _changed_by(part.actions)]
            for region in item.regions:
                if region.machine is None:
                    continue
                own = (instance_note(ctx, region.instance),) if region.instance else ()
                found += [(n, notes + own) for n, notes in changed(ctx, region.machine)]
    return found


def _changed_by(actions) -> list[ast.Name]:
    found = []
    for action in actions:
        if isinstance(action, _CHANGES):
            found += list(action.names)
        elif isinstance(action, ast.Assign):
            found.append(action.owner)
    return found
