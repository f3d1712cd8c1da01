"""Conditions of ``when`` clauses: known names, flags versus measures, units."""

from __future__ import annotations

from ..lang import ast
from ..lang.catalogue import (GAZE_SPACE, JOINT_SPACE, JOINT_VELOCITY_SPACE, ORIENTATION_SPACE,
                              POSE_SPACE, POSITION, POSITION_SPACE, TWIST_SPACE, VELOCITY)
from ..lang.units import (ANGLE, ANGULAR_VELOCITY, DIMENSIONLESS, FORCE, LENGTH,
                          LINEAR_VELOCITY, TIME, TORQUE)
from .collisions import check_collision_set
from .context import CheckContext
from .declarations import check_sensed, subject_of
from .parameters import check_body
from .values import check_quantity, space_dimensions

CONTROLLER = "controller"
DONE = "done"
VISITS = "visits"
STATE_FIELDS = (DONE, VISITS)
TASK_FLAGS = ("reached", "interpolated")
CONTROLLER_FLAGS = ("failed",)
TASK_MEASURES = ("error", "position_error", "orientation_error")
_MEASURES_BY_SPACE = {
    JOINT_SPACE: ("error",), JOINT_VELOCITY_SPACE: ("error",), TWIST_SPACE: ("error",),
    POSITION_SPACE: ("error", "position_error"),
    ORIENTATION_SPACE: ("error", "orientation_error"),
    POSE_SPACE: TASK_MEASURES,
}


def check_condition(ctx: CheckContext, condition: ast.Condition) -> None:
    """Report every problem in ``condition``."""
    if isinstance(condition, (ast.And, ast.Or)):
        for operand in condition.operands:
            check_condition(ctx, operand)
    elif isinstance(condition, ast.Not):
        check_condition(ctx, condition.operand)
    elif isinstance(condition, ast.EventCondition):
        name = condition.event.text
        if name not in ctx.symbols.events and name not in ctx.generic:
            ctx.unknown("unknown-event", "event", condition.event, ctx.symbols.events,
                        f"no action emits it: add 'emit {name}' to a state, or declare "
                        f"'event {name}' when it comes from outside the mission")
    elif isinstance(condition, ast.Contact):
        check_contact(ctx, condition)
    elif isinstance(condition, ast.Comparison):
        dimensions = measure_dimensions(ctx, condition.measure)
        value = condition.quantity
        if isinstance(value, ast.Reference):
            _compare_with_name(ctx, condition, dimensions)
            return
        if not isinstance(value, ast.Quantity):
            ctx.error("wrong-value", "a comparison needs one number", value.span,
                      "the constant or parameter compared holds something else")
            return
        if dimensions is not None:
            check_quantity(ctx, condition.quantity, dimensions,
                           f"'{_measure_text(condition.measure)}'")
    else:
        _check_flag(ctx, condition)


def _compare_with_name(ctx: CheckContext, condition: ast.Comparison, dimensions) -> None:
    """A comparison with a var (a constant was substituted before)."""
    from .variables import NAMED, describe

    name = condition.quantity.name
    if name.text in ctx.generic:
        return
    info = ctx.variables.get(name.text)
    if info is None:
        what = "var or constant" if ctx.all_variables else "constant"
        ctx.unknown("unknown-name", what, name, [*ctx.variables, *ctx.numbers],
                    "compare with a number and its unit, a var, or a constant or "
                    "parameter that holds one")
        return
    if dimensions is None:
        return
    wanted = {NAMED[d] for d in dimensions}
    if info.typed.size != 1 or info.typed.dimension not in wanted:
        ctx.error("wrong-dimension", f"'{_measure_text(condition.measure)}' is compared with "
                  f"'{name.text}', {describe(info.typed.dimension, info.typed.size)}",
                  name.span, "compare like with like")


def check_contact(ctx: CheckContext, contact: ast.Contact) -> None:
    """``contact(A, B)``: two bodies or sets, in a world whose physics has contacts."""
    known = all([check_collision_set(ctx, name) for name in (contact.first, contact.second)])
    if known and ctx.world.known and not ctx.world.simulated:
        ctx.error("no-contacts", "'contact' reads the physics, and this world has none",
                  contact.span, "run the mission on a world with a mujoco driver (run "
                  "--world VARIANT), or compare a clearance: clearance(A, B) < 1 mm")


def check_wrench(ctx: CheckContext, wrench: ast.Wrench) -> tuple[str, ...] | None:
    """``force(BODY)`` [N] or ``torque(BODY)`` [N m], with an optional axis: a body that
    a force sensor measures."""
    what = "torque" if wrench.torque else "force"
    if wrench.axis is not None and wrench.axis.text not in ("x", "y", "z"):
        ctx.unknown("unknown-field", "axis", wrench.axis, ("x", "y", "z"),
                    f"a {what} has x, y and z (in the world frame)", where=f" of a {what}")
        return None
    if not check_body(ctx, wrench.body) or not check_sensed(ctx, wrench.body):
        return None
    return (TORQUE if wrench.torque else FORCE,)


def _measure_text(measure: ast.Measure) -> str:
    if isinstance(measure, ast.Wrench):
        axis = f".{measure.axis.text}" if measure.axis else ""
        return f"{'torque' if measure.torque else 'force'}({measure.body.text}){axis}"
    if isinstance(measure, ast.Variable):
        return measure.name.text
    if isinstance(measure, ast.Member) and measure.region is not None:
        return f"{measure.owner.text}.{measure.region.text}.{measure.field.text}"
    if isinstance(measure, ast.Member):
        return f"{measure.owner.text}.{measure.field.text}"
    if isinstance(measure, ast.Distance):
        return "clearance" if isinstance(measure, ast.Clearance) else "distance"
    return "elapsed" if isinstance(measure, ast.Elapsed) else "time"


def _owner(ctx: CheckContext, member: ast.Member):
    """The task a member belongs to; ``None`` after reporting when it is not one."""
    name = member.owner.text
    if name in ctx.symbols.tasks:
        return ctx.symbols.tasks[name]
    if name in ctx.generic:
        return None
    if name in ctx.symbols.constraints:
        ctx.error("wrong-kind", f"'{name}' is a constraint: it has no '{member.field.text}'",
                  member.owner.span, "conditions read tasks (X.reached, X.error) "
                  "and controller.failed")
        return None
    holder = ctx.all_states.get(name)
    extra = (f"'{name}' is a state in the machine of '{holder}': a clause reads the states "
             "of its own machine and of the machines around it" if holder else "")
    ctx.unknown("unknown-task", "task", member.owner, list(ctx.symbols.tasks) + [CONTROLLER],
                extra)
    return None


def scoped_state(ctx: CheckContext, member: ast.Member) -> ast.StateDecl | None:
    """The state a member reads (``S.FINAL``, ``S.done``, ``S.REGION.FINAL``,
    ``S.visits``), ``None`` when it reads a task or the controller."""
    name = member.owner.text
    for machine in ctx.scope:
        if name in machine:
            state = machine[name]
            if name not in ctx.symbols.tasks or member.region is not None \
                    or member.field.text in STATE_FIELDS:
                return state
            return None
    return None


def _finals(machine: ast.Machine) -> list[str]:
    return [s.name.text for s in machine.states if s.final]


def _check_state_flag(ctx: CheckContext, member: ast.Member, state: ast.StateDecl) -> None:
    owner, field = member.owner.text, member.field.text
    if field == VISITS:
        ctx.error("wrong-condition", f"'{owner}.visits' is a count, not true or false",
                  member.span, f"compare it: {owner}.visits < 3")
        return
    if field == DONE:
        if not state.parallel:
            ctx.error("not-a-machine", f"'{owner}' is not a parallel state: it has no "
                      "'done'", member.field.span, _machine_hint(owner, state))
        return
    if member.region is not None:
        regions = {r.name.text: r for r in state.regions if r.name is not None}
        if not state.parallel:
            ctx.error("not-a-machine", f"'{owner}' is not a parallel state: it has no "
                      "regions", member.region.span, _machine_hint(owner, state))
            return
        region = regions.get(member.region.text)
        if region is None:
            ctx.unknown("unknown-region", "region", member.region, regions,
                        f"regions of '{owner}': " + ", ".join(regions),
                        where=f" of '{owner}'")
            return
        _check_final_name(ctx, member, region.machine, f"region '{member.region.text}' of "
                          f"'{owner}'")
        return
    if not state.regions:
        ctx.error("not-a-machine", f"'{owner}' has no machine: '{owner}.{field}' names a "
                  "final of a compound state or a behaviour instance", member.span,
                  "nest states in it, or instantiate a behaviour: state S: BEHAVIOR(...)")
        return
    if state.parallel:
        ctx.error("not-a-machine", f"'{owner}' is a parallel state: name the region",
                  member.field.span, f"{owner}.REGION.{field}, or {owner}.done when every "
                  "region has finished")
        return
    _check_final_name(ctx, member, state.regions[0].machine, f"'{owner}'")


def _check_final_name(ctx: CheckContext, member: ast.Member, machine: ast.Machine | None,
                      what: str) -> None:
    if machine is None:
        return
    finals = _finals(machine)
    if member.field.text not in finals:
        ctx.unknown("unknown-final", "final", member.field, finals,
                    f"finals of {what}: " + (", ".join(finals) or "none"), where=f" of {what}")


def _machine_hint(owner: str, state: ast.StateDecl) -> str:
    if state.regions:
        return f"name one of its finals: {owner}.FINAL"
    return "S.done and S.REGION.FINAL read a parallel state"


def _check_flag(ctx: CheckContext, member: ast.Member) -> None:
    field = member.field.text
    state = scoped_state(ctx, member)
    if state is not None:
        _check_state_flag(ctx, member, state)
        return
    if member.owner.text == CONTROLLER:
        if field not in CONTROLLER_FLAGS:
            ctx.unknown("unknown-field", "field", member.field, CONTROLLER_FLAGS,
                        "the controller has: failed", where=" of the controller")
        return
    if _owner(ctx, member) is None:
        return
    if field in TASK_MEASURES:
        ctx.error("wrong-condition", f"'{member.owner.text}.{field}' is a measure, "
                  "not true or false", member.span,
                  f"compare it: {member.owner.text}.{field} < 1 mm")
    elif field not in TASK_FLAGS:
        ctx.unknown("unknown-field", "field", member.field, TASK_FLAGS + TASK_MEASURES,
                    "tasks have: " + ", ".join(TASK_FLAGS + TASK_MEASURES),
                    where=f" of task '{member.owner.text}'")


def measure_dimensions(ctx: CheckContext, measure: ast.Measure) -> tuple[str, ...] | None:
    """What a measure may be compared with; ``None`` after reporting a bad measure."""
    if isinstance(measure, (ast.Elapsed, ast.Time)):
        return (TIME,)
    if isinstance(measure, ast.Wrench):
        return check_wrench(ctx, measure)
    if isinstance(measure, (ast.Variable, ast.Member)):
        return _value_dimensions(ctx, measure)
    if isinstance(measure, ast.Clearance):
        known = [check_collision_set(ctx, name) for name in (measure.first, measure.second)]
        return (LENGTH,) if all(known) else None
    if isinstance(measure, ast.Distance):
        known = [check_body(ctx, name) for name in (measure.first, measure.second)]
        return (LENGTH,) if all(known) else None
    return _member_dimensions(ctx, measure)


def _value_dimensions(ctx: CheckContext, measure) -> tuple[str, ...] | None:
    """A var or ``BODY.position.x|y|z`` compared: one number of a named dimension."""
    from .variables import NAMED, body_position, variable

    if isinstance(measure, ast.Member):
        field = measure.region.text if measure.region is not None else measure.field.text
        if not (field == "position" and ctx.world.has_body(measure.owner.text)
                and measure.owner.text not in ctx.symbols.tasks):
            return _member_dimensions(ctx, measure)
        typed = body_position(ctx, measure)
    else:
        typed = variable(ctx, measure.name, ctx.variables)
    if typed is None:
        return None
    if typed.size != 1:
        ctx.error("wrong-value", f"'{_measure_text(measure)}' is a 3-vector: compare one of "
                  "its components", measure.span, f"{_measure_text(measure)}.z")
        return None
    named = [name for name, dimension in NAMED.items() if dimension == typed.dimension]
    if not named:
        ctx.error("wrong-dimension", f"'{_measure_text(measure)}' has no unit to compare "
                  "with", measure.span, "compare a var of a named kind")
        return None
    return tuple(named)


def _member_dimensions(ctx: CheckContext, measure: ast.Member) -> tuple[str, ...] | None:
    field = measure.field.text
    state = scoped_state(ctx, measure)
    if state is not None:
        if field == VISITS:
            return (DIMENSIONLESS,)
        ctx.error("wrong-condition", f"'{measure.owner.text}.{field}' is true or false, "
                  "it cannot be compared", measure.span,
                  f"use it alone: when {measure.owner.text}.{field} -> ...")
        return None
    if measure.owner.text == CONTROLLER or field in TASK_FLAGS:
        if measure.owner.text == CONTROLLER and field not in CONTROLLER_FLAGS:
            ctx.unknown("unknown-field", "field", measure.field, CONTROLLER_FLAGS,
                        "the controller has: failed", where=" of the controller")
            return None
        ctx.error("wrong-condition", f"'{measure.owner.text}.{field}' is true or false, "
                  "it cannot be compared", measure.span,
                  f"use it alone: when {measure.owner.text}.{field} -> ...")
        return None
    task = _owner(ctx, measure)
    if task is None:
        return None
    subject = subject_of(ctx, task)
    if field not in TASK_MEASURES:
        ctx.unknown("unknown-field", "field", measure.field, TASK_FLAGS + TASK_MEASURES,
                    "tasks have: " + ", ".join(TASK_FLAGS + TASK_MEASURES),
                    where=f" of task '{measure.owner.text}'")
        return None
    if subject is None:
        return None
    allowed = _MEASURES_BY_SPACE.get(subject.space, ("error",))
    if field not in allowed:
        ctx.error("unknown-field", f"a {subject.kind.name} task has no '{field}'",
                  measure.field.span, "it has: " + ", ".join(TASK_FLAGS + allowed))
        return None
    if field == "error" and subject.space == POSE_SPACE:
        ctx.error("mixed-error", f"'{measure.owner.text}.error' mixes metres and radians: "
                  "a pose task's error joins its position and orientation errors",
                  measure.field.span, f"compare {measure.owner.text}.position_error with a "
                  f"length and {measure.owner.text}.orientation_error with an angle")
        return None
    if field == "position_error":
        return (LENGTH,)
    if field == "orientation_error" or subject.space == GAZE_SPACE:
        return (ANGLE,)
    if subject.space == TWIST_SPACE:
        return (LINEAR_VELOCITY, ANGULAR_VELOCITY)
    symbol = VELOCITY if subject.space == JOINT_VELOCITY_SPACE else POSITION
    return space_dimensions(symbol, subject.space, subject.joints)


def members_of(condition: ast.Condition) -> list[ast.Member]:
    """The ``owner.field`` members a condition reads, compared or not, in order."""
    if isinstance(condition, (ast.And, ast.Or)):
        return [m for c in condition.operands for m in members_of(c)]
    if isinstance(condition, ast.Not):
        return members_of(condition.operand)
    if isinstance(condition, ast.Comparison):
        condition = condition.measure
    return [condition] if isinstance(condition, ast.Member) else []


def tasks_read(condition: ast.Condition) -> list[ast.Name]:
    """Task names a condition reads (``X.reached``, ``X.error``...), in order."""
    return [m.owner for m in members_of(condition) if m.owner.text != CONTROLLER]
