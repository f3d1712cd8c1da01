"""Limits assigned by actions stay ordered: ``limits.min_position = ...`` in a block
must not leave ``min_position`` above ``max_position``, nor ``c.min_distance = ...`` a
collision constraint's ``min_distance`` at or above its ``influence``.

The limit a block does not assign is the one the constraint declares, else the URDF's;
a block that assigns both is judged on the values it assigns (actions of one block run
in the same cycle, before the controller).
"""

from __future__ import annotations

from ..lang import ast
from ..lang.catalogue import COLLISION_SETS
from .collisions import check_distances
from .context import CheckContext
from .declarations import subject_of
from .parameters import check_order

_DISTANCES = ("min_distance", "influence")


def check_assigned_order(ctx: CheckContext,
                         assigned: list[tuple[ast.Assign, tuple[float, ...] | None]]) -> None:
    """Report each ordered pair of limits (``kind.ordered``) that the assignments of one
    block invert, at the first assignment of the pair."""
    by_owner: dict[str, dict[str, tuple[ast.Value, tuple[float, ...] | None]]] = {}
    for action, numbers in assigned:
        by_owner.setdefault(action.owner.text, {})[action.field.text] = (action.value, numbers)
    for owner, values in by_owner.items():
        decl = ctx.symbols.constraints.get(owner)
        subject = subject_of(ctx, decl) if decl is not None else None
        if subject is None:
            continue
        declared = ctx.declared.get(owner, {})
        if subject.kind.subject == COLLISION_SETS:
            _check_distances(ctx, subject.kind, decl.name, declared, [
                (action, numbers) for action, numbers in assigned
                if action.owner.text == owner and action.field.text in _DISTANCES])
            continue
        for low, high in subject.kind.ordered:
            mine = [name for name in (low, high) if name in values]
            if not mine:
                continue
            merged = {**declared, **values}
            kept = next((n for n in (low, high) if n not in values and n in declared), None)
            check_order(ctx, low, high, {n: merged[n] for n in (low, high) if n in merged},
                        subject.joints, located=mine[0], declared=kept)


def _check_distances(ctx: CheckContext, kind, name: ast.Name, declared: dict,
                     assigned: list) -> None:
    """A collision constraint's distances after each assignment, in order (the run
    checks each one as it is made)."""
    given: dict = {}
    for action, numbers in assigned:
        if not numbers:
            return
        given[action.field.text] = (action.value, numbers[0])
        if not check_distances(ctx, kind, {action.field.text: given[action.field.text]},
                               name, {**declared, **given}):
            return
