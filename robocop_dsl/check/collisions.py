"""Checks of ``collision_avoidance(A, B)`` declarations: two sets that name bodies or
joint groups with collision geometry, an ``influence`` above ``min_distance``, and no
pair already closer than ``min_distance`` in the world's initial posture (a warning
with the distance). What the geometry answers is kept between runs
(:mod:`~robocop_dsl.world.collision_facts`)."""

from __future__ import annotations

from ..lang import ast
from ..lang.catalogue import Kind
from .context import CheckContext
from .parameters import Subject, check_parameters


def check_collision_constraint(ctx: CheckContext, decl: ast.ConstraintDecl, kind: Kind) -> None:
    """Report every problem of a ``collision_avoidance`` declaration."""
    if len(decl.arguments) != 2:
        ctx.error("wrong-arguments", f"{kind.name} takes two sets (bodies or joint groups), "
                  f"not {len(decl.arguments)}", decl.kind.span,
                  f"write {kind.name}(BODY_OR_GROUP, BODY_OR_GROUP)")
        return
    known = [check_collision_set(ctx, argument) for argument in decl.arguments]
    given = [(p.name, p.value) for p in decl.parameters]
    numbers = check_parameters(ctx, given, kind, Subject(kind), f"constraint '{decl.name.text}'",
                               decl.name.span)
    values = {name: (value, found[0]) for name, (value, found) in numbers.items() if found}
    ctx.declared.setdefault(decl.name.text, values)
    if not check_distances(ctx, kind, values, decl.name):
        return
    generic = any(argument.text in ctx.generic for argument in decl.arguments)
    if all(known) and ctx.world.known and not generic:
        _check_initial_posture(ctx, decl, values.get(
            "min_distance", (None, kind.parameter("min_distance").default))[1])


def check_distances(ctx: CheckContext, kind: Kind, values: dict, name: ast.Name,
                    declared: dict | None = None) -> bool:
    """Whether ``influence`` is above ``min_distance`` [m] (``values``: name -> (value,
    metres), else ``declared``'s, else the defaults); reported at the value that
    ``values`` gives, else at ``name``."""
    merged = {**(declared or {}), **values}
    min_distance = merged.get("min_distance", (None, kind.parameter("min_distance").default))
    influence = merged.get("influence", (None, kind.parameter("influence").default))
    if influence[1] > min_distance[1]:
        return True
    where = next((values[n][0] for n in ("influence", "min_distance") if n in values), name)
    kept = [f"{n} as given at {ctx.where(declared[n][0].span)}"
            for n in ("influence", "min_distance") if declared and n in declared
            and n not in values]
    ctx.error("wrong-value", f"influence ({_cm(influence[1])}) must be above "
              f"min_distance ({_cm(min_distance[1])})" + (f", {kept[0]}" if kept else ""),
              where.span, "the constraint acts on the pairs between min_distance and influence")
    return False


def check_collision_set(ctx: CheckContext, argument: ast.Name) -> bool:
    """A body or joint group with collision geometry; ``False`` after reporting one that
    is not (``True`` for a behaviour's parameter, checked where it is bound)."""
    from ..world.collision_facts import collision_facts

    world = ctx.world
    if argument.text in ctx.generic:
        return True
    if not (world.has_body(argument.text) or world.has_joints(argument.text)):
        ctx.unknown("unknown-body", "body or joint group", argument,
                    world.body_names() + world.joint_names())
        return False
    if world.known and not collision_facts(world.world).set_bodies(argument.text):
        ctx.error("no-collision-geometry", f"'{argument.text}' has no collision geometry",
                  argument.span, "collision geometry comes from the URDFs' <collision> "
                  "elements; name a body or joint group that has some")
        return False
    return True


def _check_initial_posture(ctx: CheckContext, decl: ast.ConstraintDecl,
                           min_distance: float) -> None:
    from ..world.collision_facts import collision_facts

    first, second = (argument.text for argument in decl.arguments)
    facts = collision_facts(ctx.world.world)
    for body, other, distance in facts.closest_at_start(first, second, min_distance):
        ctx.warning("collision-at-start", f"'{body}' and '{other}' "
                    f"are {_cm(distance)} apart in the initial posture, closer than "
                    f"min_distance ({_cm(min_distance)})", decl.name.span,
                    "the constraint will push them apart from the first cycle; change the "
                    "world's initial posture, min_distance or allowed_collisions")


def _cm(metres: float) -> str:
    return f"{metres * 100:.3g} cm"
