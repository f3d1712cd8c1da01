"""Parallel regions: a task or constraint is changed by one region at most.

Changing means ``enable``, ``disable``, ``reset`` or assigning a field, in any block or
transition of a region's machine at any depth (behaviour instances included). Reading
is free.
"""

from __future__ import annotations

from ..lang import ast
from .context import CheckContext

_CHANGES = (ast.Enable, ast.Disable, ast.Reset)


def check_regions(ctx: CheckContext, machine: ast.Machine) -> None:
    """Report every task or constraint changed by two regions of one parallel state."""
    for state in machine.states:
        if state.parallel:
            _check_parallel(ctx, state)
        for region in state.regions:
            if region.machine is not None:
                check_regions(ctx, region.machine)


def _check_parallel(ctx: CheckContext, state: ast.StateDecl) -> None:
    owners: dict[str, tuple[str, ast.Name]] = {}
    for region in state.regions:
        if region.machine is None or region.name is None:
            continue
        mine: dict[str, ast.Name] = {}
        for name in changed(region.machine):
            mine.setdefault(name.text, name)
        for text, name in mine.items():
            if text not in owners:
                owners[text] = (region.name.text, name)
                continue
            first_region, first = owners[text]
            ctx.error("region-conflict", f"'{text}' is changed by regions '{first_region}' "
                      f"({ctx.where(first.span)}) and '{region.name.text}' "
                      f"({ctx.where(name.span)}) of '{state.name.text}'", name.span,
                      "a task or constraint is changed by one region at most: change it in "
                      "one region, or in the parallel state's own blocks")


def changed(machine: ast.Machine) -> list[ast.Name]:
    """The task and constraint names a machine changes, at any depth, in source order."""
    found = []
    for item in machine.items:
        if isinstance(item, ast.Transition):
            found += _changed_by(item.actions)
        elif isinstance(item, ast.StateDecl):
            for part in item.parts:
                found += _changed_by(part.actions)
            for region in item.regions:
                if region.machine is not None:
                    found += changed(region.machine)
    return found


def _changed_by(actions) -> list[ast.Name]:
    found = []
    for action in actions:
        if isinstance(action, _CHANGES):
            found += list(action.names)
        elif isinstance(action, ast.Assign):
            found.append(action.owner)
    return found
