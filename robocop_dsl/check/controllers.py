"""Which controller runs each task and constraint.

A mission runs the controller it names (``controller NAME``) or the world's only one.
When it names none and the world's controllers drive pairwise disjoint joint groups,
it runs them all, cascaded, each at its own period: a task or constraint then belongs to
the controller whose joints move its subject (the joints of a joint group; for a body,
the joints between the world and the body). A subject that no controller moves, or that
joints of several controllers move, is an error. The state machine runs with the fastest
controller (the smallest time step; the first declared on a tie).
"""

from __future__ import annotations

from ..lang import ast
from ..lang.catalogue import COLLISION_SETS, CONSTRAINTS, JOINT_GROUP, TASKS
from .context import CheckContext, WorldNames


def cascade_controllers(names: WorldNames) -> list[str]:
    """The world's controllers, fastest first, when there are several on pairwise
    disjoint joint groups; else an empty list."""
    controllers = names.controller_names()
    if len(controllers) < 2:
        return []
    seen: set = set()
    for controller in controllers:
        joints = names.controller_joints(controller)
        if not joints or joints & seen:
            return []
        seen |= joints
    order = {name: index for index, name in enumerate(controllers)}
    return sorted(controllers, key=lambda c: (names.controller_time_step(c), order[c]))


def mission_controllers(names: WorldNames, mission: ast.Mission) -> list[str]:
    """The controllers a mission runs: the named one, the world's only one, or the
    cascade (fastest first); empty when the world gives no answer."""
    declared = mission.first(ast.ControllerDecl)
    if declared is not None:
        return [declared.name.text]
    controllers = names.controller_names()
    return controllers if len(controllers) == 1 else cascade_controllers(names)


def subject_joints(names: WorldNames, decl) -> set:
    """The moving joints that move a declaration's subject (empty when unknown)."""
    registry = TASKS if isinstance(decl, ast.TaskDecl) else CONSTRAINTS
    kind = registry.get(decl.kind.text)
    if kind is not None and kind.subject == COLLISION_SETS and len(decl.arguments) == 2:
        return set().union(*(names.group_joints(a.text) if names.joints(a.text) is not None
                             else names.body_joints(a.text) for a in decl.arguments))
    if kind is None or len(decl.arguments) != 1:
        return set()
    subject = decl.arguments[0].text
    if kind.subject == JOINT_GROUP:
        return names.group_joints(subject)
    return names.body_joints(subject)


def owners(names: WorldNames, controllers: list[str], decl) -> list[str]:
    """The controllers, among ``controllers``, whose joints move ``decl``'s subject."""
    moving = subject_joints(names, decl)
    return [c for c in controllers if names.controller_joints(c) & moving]


def controller_of(names: WorldNames, controllers: list[str], decl) -> str:
    """The controller that runs ``decl`` (of a mission that checked without errors)."""
    if len(controllers) == 1:
        return controllers[0]
    return owners(names, controllers, decl)[0]


def check_assignment(ctx: CheckContext, mission: ast.Mission) -> None:
    """In a cascade, every task and constraint is moved by exactly one controller (and
    a ``body_pose`` task's body by six of its dofs, a warning)."""
    if not ctx.world.known or mission.first(ast.ControllerDecl) is not None:
        return
    controllers = cascade_controllers(ctx.world)
    if not controllers:
        return
    for decl in mission.tasks + mission.constraints:
        if not subject_joints(ctx.world, decl):
            if _known_subject(ctx.world, decl):
                _report_none(ctx, decl, controllers)
            continue
        found = owners(ctx.world, controllers, decl)
        if not found:
            _report_none(ctx, decl, controllers)
        elif len(found) == 1 and isinstance(decl, ast.TaskDecl):
            _few_dofs(ctx, decl, subject_joints(ctx.world, decl)
                      & ctx.world.controller_joints(found[0]))
        elif len(found) > 1:
            groups = ", ".join(f"{c} ({ctx.world.controller_group(c)})" for c in found)
            ctx.error("several-controllers", f"'{decl.arguments[0].text}' is moved by the "
                      f"joints of several controllers: {groups}", decl.arguments[0].span,
                      f"a cascaded {_what(decl)} belongs to one controller: split it in "
                      "one per controller's joint group")


def _known_subject(names: WorldNames, decl) -> bool:
    registry = TASKS if isinstance(decl, ast.TaskDecl) else CONSTRAINTS
    kind = registry.get(decl.kind.text)
    if kind is not None and kind.subject == COLLISION_SETS and len(decl.arguments) == 2:
        return all(names.joints(a.text) is not None or names.world.has_body(a.text)
                   for a in decl.arguments)
    if kind is None or len(decl.arguments) != 1:
        return False
    subject = decl.arguments[0].text
    if kind.subject == JOINT_GROUP:
        return names.joints(subject) is not None
    return names.world.has_body(subject)


def _report_none(ctx: CheckContext, decl, controllers: list[str]) -> None:
    groups = ", ".join(f"{c} ({ctx.world.controller_group(c)})" for c in controllers)
    ctx.error("no-controller", f"no controller moves '{decl.arguments[0].text}'",
              decl.arguments[0].span, f"a cascaded {_what(decl)} must be moved by the "
              f"joints of one controller: {groups}")


def _what(decl) -> str:
    return "task" if isinstance(decl, ast.TaskDecl) else "constraint"


def check_driven(ctx: CheckContext, mission: ast.Mission) -> None:
    """With one controller, every joint group a task or constraint names is driven by
    it, every body a task moves is moved by its joints, and a ``body_pose`` task has the
    six directions it asks for."""
    if not ctx.world.known:
        return
    controllers = mission_controllers(ctx.world, mission)
    if len(controllers) != 1 or controllers[0] not in ctx.world.controller_names():
        return
    controller = controllers[0]
    driven = ctx.world.controller_joints(controller)
    group = ctx.world.controller_group(controller)
    if not driven:
        return
    for decl in mission.tasks + mission.constraints:
        registry = TASKS if isinstance(decl, ast.TaskDecl) else CONSTRAINTS
        kind = registry.get(decl.kind.text)
        if kind is None or kind.subject == COLLISION_SETS or len(decl.arguments) != 1 \
                or not _known_subject(ctx.world, decl):
            continue
        subject = decl.arguments[0]
        if kind.subject == JOINT_GROUP:
            outside = sorted(ctx.world.group_joints(subject.text) - driven)
            if outside:
                ctx.error("not-driven", f"'{subject.text}' has joints that controller "
                          f"'{controller}' does not drive: {', '.join(outside)}",
                          subject.span, f"'{controller}' drives the joint group '{group}': "
                          "name a group inside it, or give the controller a group that "
                          "holds these joints (the world's joint_groups)")
        elif isinstance(decl, ast.TaskDecl):
            moving = ctx.world.body_joints(subject.text) & driven
            if not moving:
                ctx.error("not-driven", f"no joint that controller '{controller}' drives "
                          f"moves '{subject.text}'", subject.span,
                          f"'{controller}' drives the joint group '{group}': the task "
                          "could never move this body")
            else:
                _few_dofs(ctx, decl, moving)


def _few_dofs(ctx: CheckContext, decl, moving: set) -> None:
    """Warn at a ``body_pose`` task whose body fewer than six driven dofs (of the joints
    ``moving``) move."""
    if decl.kind.text != "body_pose":
        return
    dofs = sum(ctx.world.world.joint(j).dofs for j in moving)
    if dofs < 6:
        ctx.warning("few-dofs", f"only {dofs} driven dofs move '{decl.arguments[0].text}': "
                    "a body_pose task asks for 6 directions", decl.kind.span,
                    "it cannot reach every pose: use body_position or body_orientation, or "
                    "drive more joints")
