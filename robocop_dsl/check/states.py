"""States: the start, final states and outcomes, action blocks, actions and transitions."""

from __future__ import annotations

from ..lang import ast
from .conditions import check_condition
from .context import CheckContext
from .declarations import subject_of
from .parameters import check_body, check_value

OUTCOMES = ("success", "failure")
_FINAL_PARTS = ("enter",)


def start_state(ctx: CheckContext, mission: ast.Mission) -> str | None:
    """The start state's name: the one named by ``start``, else the first declared."""
    declared = mission.first(ast.StartDecl)
    if declared is None:
        return mission.states[0].name.text if mission.states else None
    name = declared.state.text
    return name if name in ctx.symbols.states else None


def check_start(ctx: CheckContext, mission: ast.Mission) -> None:
    declared = mission.first(ast.StartDecl)
    if declared is not None:
        name = declared.state
        kinds = (("task", ctx.symbols.tasks), ("constraint", ctx.symbols.constraints))
        other = next((kind for kind, table in kinds if name.text in table), None)
        if other is not None:
            ctx.error("start-not-state", f"start names the {other} '{name.text}', not a state",
                      name.span, _did_you_mean_state(ctx, name))
            return
        if name.text not in ctx.symbols.states:
            ctx.unknown("unknown-state", "state", name, ctx.symbols.states)
            return
    start = start_state(ctx, mission)
    if start is not None and ctx.symbols.states[start].final:
        state = ctx.symbols.states[start]
        ctx.warning("start-is-final", f"the mission starts in the final state '{start}'",
                    (declared.state if declared else state.name).span,
                    "it ends as soon as it starts")


def _did_you_mean_state(ctx: CheckContext, name: ast.Name) -> str:
    states = [n for n, s in ctx.symbols.states.items() if not s.final]
    return "states: " + ", ".join(states) if states else "declare a state first"


def check_states(ctx: CheckContext, mission: ast.Mission) -> None:
    """Every state's blocks and transitions, then the top-level guards."""
    for state in mission.states:
        _check_state(ctx, state)
    for guard in mission.guards:
        check_transition(ctx, guard)


def _check_state(ctx: CheckContext, state: ast.StateDecl) -> None:
    seen: dict[str, ast.ActionBlock] = {}
    for block in state.blocks:
        if block.kind in seen:
            ctx.error("duplicate-declaration", f"a second '{block.kind}' block in state "
                      f"'{state.name.text}'", block.span,
                      f"the first is at line {seen[block.kind].span.line}; merge them")
        seen.setdefault(block.kind, block)
        for action in block.actions:
            check_action(ctx, action)
    if state.final:
        _check_final(ctx, state)
    for transition in state.transitions:
        check_transition(ctx, transition)


def _check_final(ctx: CheckContext, state: ast.StateDecl) -> None:
    if state.outcome is not None and state.outcome.text not in OUTCOMES:
        ctx.unknown("unknown-outcome", "outcome", state.outcome, OUTCOMES,
                    "a final state ends in success (the default) or failure")
    for part in state.parts:
        if isinstance(part, ast.Transition):
            ctx.error("final-with-clauses", f"final state '{state.name.text}' has a "
                      "'when' clause: the mission ends there", part.span,
                      f"make it 'state {state.name.text}' or remove the clause")
        elif part.kind not in _FINAL_PARTS:
            ctx.error("final-with-clauses", f"final state '{state.name.text}' has an "
                      f"'{part.kind}' block that never runs", part.span,
                      "a final state may only have an 'enter' block")


def check_transition(ctx: CheckContext, transition: ast.Transition) -> None:
    check_condition(ctx, transition.condition)
    target = transition.target
    if target.text not in ctx.symbols.states:
        ctx.unknown("unknown-state", "state", target, ctx.symbols.states)


def check_action(ctx: CheckContext, action: ast.Action) -> None:
    """One action of an ``enter``/``during``/``exit`` block."""
    if isinstance(action, (ast.Enable, ast.Disable)):
        for name in action.names:
            if name.text not in ctx.symbols.tasks and name.text not in ctx.symbols.constraints:
                ctx.unknown("unknown-task", "task or constraint", name,
                            ctx.symbols.controlled())
    elif isinstance(action, ast.Reset):
        for name in action.names:
            if name.text in ctx.symbols.constraints:
                ctx.error("wrong-kind", f"'{name.text}' is a constraint: only tasks have "
                          "an interpolator to reset", name.span)
            elif name.text not in ctx.symbols.tasks:
                ctx.unknown("unknown-task", "task", name, ctx.symbols.tasks)
    elif isinstance(action, ast.Assign):
        _check_assign(ctx, action)
    elif isinstance(action, ast.Attach):
        if all([check_body(ctx, action.body), check_body(ctx, action.parent)]) \
                and action.body.text == action.parent.text:
            ctx.error("wrong-value", f"'{action.body.text}' cannot be attached to itself",
                      action.span)
    elif isinstance(action, ast.Detach):
        check_body(ctx, action.body)


def _check_assign(ctx: CheckContext, action: ast.Assign) -> None:
    owner = action.owner.text
    decl = ctx.symbols.tasks.get(owner) or ctx.symbols.constraints.get(owner)
    if decl is None:
        ctx.unknown("unknown-task", "task or constraint", action.owner,
                    ctx.symbols.controlled())
        return
    subject = subject_of(ctx, decl)
    if subject is None:
        return
    settable = [p for p in subject.kind.parameters if p.settable]
    parameter = subject.kind.parameter(action.field.text)
    if parameter is None or not parameter.settable:
        names = [p.name for p in settable]
        extra = (f"'{action.field.text}' is set in the declaration only" if parameter
                 else f"a {subject.kind.name} can set: {', '.join(names) or 'nothing'}")
        if parameter is not None:
            ctx.error("unknown-field", f"'{owner}.{action.field.text}' cannot be changed "
                      "by an action", action.field.span, extra)
        else:
            ctx.unknown("unknown-field", "field", action.field, names, extra,
                        where=f" of {subject.kind.name} task '{owner}'"
                        if owner in ctx.symbols.tasks else f" of constraint '{owner}'")
        return
    check_value(ctx, parameter, action.value, subject, f"'{owner}.{action.field.text}'")
