"""Machines and their states: start, finals and outcomes, blocks, actions, clauses and
where they lead, regions. Runs on the expanded tree (see :mod:`.expand`)."""

from __future__ import annotations

from ..lang import ast
from ..lang.catalogue import SWITCH
from ..world.description import ROOT as WORLD
from .conditions import check_condition
from .context import CheckContext
from .declarations import subject_of
from .expand import instance_note
from .assigned_limits import check_assigned_order
from .parameters import check_body, check_value
from .variables import check_log, check_set_var, declared_variables

OUTCOMES = ("success", "failure")
_DECLARE = ("declare it: task NAME: TYPE(SUBJECT) { ... } or constraint NAME: TYPE(...), "
            "or import the file that does")
_FINAL_PARTS = ("enter",)
DONE = "done"


def check_machines(ctx: CheckContext, mission: ast.Mission) -> None:
    """The mission's machine and every machine inside it."""
    ctx.mission_variables = declared_variables(ctx, mission.machine, {})
    check_machine(ctx, mission.machine, (), root=True)


def check_machine(ctx: CheckContext, machine: ast.Machine, scope: tuple,
                  root: bool = False) -> None:
    """One machine: ``scope`` is the chain of enclosing machines' states (innermost
    first), which clauses may read but never lead to. It sees the vars it declares and
    those of the machines around it (the mission's own are declared once, before)."""
    visible = ctx.variables
    ctx.variables = (ctx.mission_variables if root
                     else declared_variables(ctx, machine, visible))
    try:
        _check_machine(ctx, machine, scope, root)
    finally:
        ctx.variables = visible


def _check_machine(ctx: CheckContext, machine: ast.Machine, scope: tuple,
                   root: bool) -> None:
    local: dict[str, ast.StateDecl] = {}
    for state in machine.states:
        first = local.get(state.name.text)
        if first is not None:
            ctx.error("duplicate-name", f"state '{state.name.text}' is already declared",
                      state.name.span, f"first declared at {ctx.where(first.name.span)}")
            continue
        local[state.name.text] = state
        task = ctx.symbols.tasks.get(state.name.text)
        if task is not None and (state.regions or state.instance is not None):
            ctx.error("duplicate-name", f"state '{state.name.text}' has the name of a task",
                      state.name.span, f"'{state.name.text}.FIELD' would read the state or "
                      f"the task declared at {ctx.where(task.name.span)}: rename the state")
    scope = (local, *scope)
    _check_start(ctx, machine, local, root)
    for state in machine.states:
        _check_state(ctx, state, scope, root)
    previous = ctx.scope
    ctx.scope = scope
    for guard in machine.guards:
        check_transition(ctx, guard, local)
    ctx.scope = previous


def _check_start(ctx: CheckContext, machine: ast.Machine, local: dict, root: bool) -> None:
    declared = machine.start
    if declared is not None:
        name = declared.state
        kinds = (("task", ctx.symbols.tasks), ("constraint", ctx.symbols.constraints))
        other = next((kind for kind, table in kinds if name.text in table), None)
        if other is not None:
            ctx.error("start-not-state", f"start names the {other} '{name.text}', not a state",
                      name.span, _states_hint(local))
            return
        if name.text not in local:
            ctx.unknown("unknown-state", "state", name, local,
                        "start names a state of its own machine")
            return
    start = declared.state.text if declared else next(iter(local), None)
    if start is not None and local[start].final:
        ctx.warning("start-is-final", f"the {'mission' if root else 'machine'} starts in "
                    f"the final state '{start}'",
                    (declared.state if declared else local[start].name).span,
                    "it ends as soon as it starts")


def _states_hint(local: dict, finals: bool = False) -> str:
    states = [n for n, s in local.items() if finals or not s.final]
    return "states: " + ", ".join(states) if states else "declare a state first"


def _check_state(ctx: CheckContext, state: ast.StateDecl, scope: tuple, root: bool) -> None:
    seen: dict[str, ast.ActionBlock] = {}
    for block in state.blocks:
        if block.kind in seen:
            ctx.error("duplicate-declaration", f"a second '{block.kind}' block in state "
                      f"'{state.name.text}'", block.span,
                      f"the first is at {ctx.where(seen[block.kind].span)}; merge them")
        seen.setdefault(block.kind, block)
        check_actions(ctx, block.actions)
    if state.final:
        _check_final(ctx, state, root)
    previous = ctx.scope
    ctx.scope = scope
    for transition in state.transitions:
        check_transition(ctx, transition, scope[0])
    ctx.scope = previous
    if state.parallel and not state.regions:
        ctx.error("missing-declaration", f"parallel state '{state.name.text}' has no region",
                  state.name.span, "add: region NAME { ... } or region NAME: BEHAVIOR(...)")
    regions: dict[str, ast.Region] = {}
    for region in state.regions:
        name = region.name.text if region.name else None
        if name in regions:
            ctx.error("duplicate-name", f"region '{name}' is already declared in "
                      f"'{state.name.text}'", region.name.span,
                      f"first declared at {ctx.where(regions[name].name.span)}")
            continue
        regions[name] = region
        _check_region(ctx, state, region, scope)


def _check_region(ctx: CheckContext, state: ast.StateDecl, region: ast.Region,
                  scope: tuple) -> None:
    if region.name is not None and region.name.text == DONE:
        ctx.error("region-named-done", "a region cannot be named 'done'", region.name.span,
                  "S.done already means: every region is in a final state")
    if region.machine is None:
        return
    notes, owner, visible = ctx.notes, ctx.owner, ctx.variables
    if region.instance is not None:
        ctx.notes = (instance_note(ctx, region.instance), *notes)
        ctx.variables = ctx.mission_variables
    ctx.owner = state.name.text + (f".{region.name.text}" if region.name else "")
    check_machine(ctx, region.machine, scope)
    ctx.notes, ctx.owner, ctx.variables = notes, owner, visible


def _check_final(ctx: CheckContext, state: ast.StateDecl, root: bool) -> None:
    if state.outcome is not None:
        if not root:
            ctx.error("nested-outcome", f"final '{state.name.text}' of a nested machine has "
                      f"an outcome", state.outcome.span, "': failure' is only for the "
                      "mission's own finals: a nested final is an outcome its parent's "
                      "clauses handle")
        elif state.outcome.text not in OUTCOMES:
            ctx.unknown("unknown-outcome", "outcome", state.outcome, OUTCOMES,
                        "a final state ends in success (the default) or failure")
    if state.regions or state.instance is not None:
        ctx.error("final-with-clauses", f"final state '{state.name.text}' has a machine "
                  "that never runs", state.name.span, "make it a state, or move the machine "
                  "into a state before it")
    for part in state.parts:
        if isinstance(part, ast.Transition):
            ctx.error("final-with-clauses", f"final state '{state.name.text}' has a "
                      f"'when' clause: {'the mission' if root else 'its machine'} ends "
                      "there", part.span,
                      f"make it 'state {state.name.text}' or remove the clause")
        elif part.kind not in _FINAL_PARTS:
            ctx.error("final-with-clauses", f"final state '{state.name.text}' has an "
                      f"'{part.kind}' block that never runs", part.span,
                      "a final state may only have an 'enter' block")


def check_transition(ctx: CheckContext, transition: ast.Transition, local: dict) -> None:
    """A clause's condition, its actions and its target, a state of ``local``."""
    check_condition(ctx, transition.condition)
    check_actions(ctx, transition.actions)
    target = transition.target
    if target.text in local:
        return
    holder = ctx.all_states.get(target.text)
    if any(target.text in machine for machine in ctx.scope[1:]) and ctx.owner:
        state, _, region = ctx.owner.partition(".")
        machine = f"region '{region}' of '{state}'" if region else f"the machine of '{state}'"
        hint = (f"leave {machine} through a final ('final NAME') and a clause of '{state}': "
                f"when {ctx.owner}.NAME -> {target.text}")
    elif holder is not None:
        hint = (f"'{target.text}' is in the machine of '{holder}': lead to '{holder}', whose "
                "machine begins in its start state")
    else:
        ctx.unknown("unknown-state", "state", target, local, _states_hint(local, True))
        return
    ctx.error("transition-out-of-machine", f"'{target.text}' is not a state of this machine: "
              "a clause leads to a state of its own machine", target.span, hint)


def check_actions(ctx: CheckContext, actions) -> None:
    """The actions of a block or a transition, and the limits they leave in place."""
    assigned = []
    moved: dict[str, str] = {}
    for action in actions:
        numbers = check_action(ctx, action, moved)
        if isinstance(action, ast.Assign):
            assigned.append((action, numbers))
    check_assigned_order(ctx, assigned)


def check_action(ctx: CheckContext, action: ast.Action,
                 moved: dict[str, str] | None = None) -> tuple[float, ...] | None:
    """One action of an ``enter``/``during``/``exit`` block or of a transition; for an
    assignment, the numbers it assigns [SI] when usable. ``moved``: the parent each body
    has after the block's earlier attaches and detaches (updated)."""
    moved = {} if moved is None else moved
    if isinstance(action, (ast.Enable, ast.Disable)):
        for name in action.names:
            if name.text not in ctx.symbols.tasks and name.text not in ctx.symbols.constraints \
                    and name.text not in ctx.generic:
                ctx.unknown("unknown-task", "task or constraint", name,
                            ctx.symbols.controlled(), _DECLARE)
    elif isinstance(action, ast.Reset):
        for name in action.names:
            if name.text in ctx.symbols.constraints:
                ctx.error("wrong-kind", f"'{name.text}' is a constraint: only tasks have "
                          "an interpolator to reset", name.span)
            elif name.text not in ctx.symbols.tasks and name.text not in ctx.generic:
                ctx.unknown("unknown-task", "task", name, ctx.symbols.tasks)
    elif isinstance(action, ast.Assign):
        return _check_assign(ctx, action)
    elif isinstance(action, ast.SetVar):
        check_set_var(ctx, action)
    elif isinstance(action, ast.Log):
        check_log(ctx, action)
    elif isinstance(action, ast.Attach):
        body, parent = action.body.text, action.parent.text
        if all([check_body(ctx, action.body), check_body(ctx, action.parent)]):
            if body == parent:
                ctx.error("wrong-value", f"'{body}' cannot be attached to itself", action.span)
            elif body != WORLD and ctx.world.hangs_from(parent, body, moved):
                earlier = " (after this block's earlier attaches)" if moved else ""
                ctx.error("wrong-value", f"cannot attach '{body}' to '{parent}': '{parent}' "
                          f"hangs from '{body}'{earlier}", action.parent.span,
                          "attach it to a body that does not move with it")
            else:
                _check_free(ctx, action.body, "attach")
                moved[body] = parent
    elif isinstance(action, ast.Detach):
        if check_body(ctx, action.body):
            _check_free(ctx, action.body, "detach")
            moved[action.body.text] = WORLD
    return None


def _check_free(ctx: CheckContext, body, verb: str) -> None:
    """A body a joint moves (a robot's link) is never attached nor detached; in a world
    run by physics, only a free body can be welded and released."""
    world = ctx.world
    if body.text == WORLD:
        ctx.error("not-free", f"cannot {verb} the world", body.span, "attach a body the "
                  "world places (a part, a point) to a body, and detach it")
        return
    if not world.known:
        return
    moved_by = [] if world.simulated else sorted(world.body_joints(body.text))
    if moved_by:
        ctx.error("not-free", f"cannot {verb} '{body.text}': joint '{moved_by[0]}' moves it "
                  "(it belongs to a robot)", body.span, "attach a body the world places "
                  "(a part, a point) to the robot's body, not the other way round")
        return
    if world.simulated and body.text not in world.free_bodies():
        free = world.free_bodies()
        ctx.error("not-free", f"cannot {verb} '{body.text}' in physics: it is not a free "
                  "body", body.span,
                  f"give its model 'free: true' in the world file (free bodies: "
                  f"{', '.join(free) or 'none'})")


def _check_assign(ctx: CheckContext, action: ast.Assign) -> tuple[float, ...] | None:
    owner = action.owner.text
    if owner in ctx.generic:
        return None
    decl = ctx.symbols.tasks.get(owner) or ctx.symbols.constraints.get(owner)
    if decl is None:
        ctx.unknown("unknown-task", "task or constraint", action.owner,
                    ctx.symbols.controlled())
        return None
    subject = subject_of(ctx, decl)
    if subject is None:
        return None
    settable = [p for p in subject.kind.parameters if p.settable]
    parameter = subject.kind.parameter(action.field.text)
    if parameter is None or not parameter.settable:
        names = [p.name for p in settable]
        extra = (f"'{action.field.text}' is set in the declaration only" if parameter
                 else f"a {subject.kind.name} can set: {', '.join(names) or 'nothing'}")
        if parameter is not None and parameter.kind == SWITCH:
            extra = f"write: enable {owner} (or disable {owner})"
        if parameter is not None:
            ctx.error("unknown-field", f"'{owner}.{action.field.text}' cannot be changed "
                      "by an action", action.field.span, extra)
        else:
            ctx.unknown("unknown-field", "field", action.field, names, extra,
                        where=f" of {subject.kind.name} task '{owner}'"
                        if owner in ctx.symbols.tasks else f" of constraint '{owner}'")
        return None
    if ctx.opaque(action.value):
        return None
    ctx.in_target = action.field.text == "target"
    try:
        return check_value(ctx, parameter, action.value, subject,
                           f"'{owner}.{action.field.text}'")
    finally:
        ctx.in_target = False
