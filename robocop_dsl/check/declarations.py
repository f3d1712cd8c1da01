"""Top-level declarations: one header, one world, the controller, tasks and constraints."""

from __future__ import annotations

from ..diagnostics import Span
from ..lang import ast
from ..lang.catalogue import COLLISION_SETS, CONSTRAINTS, JOINT_GROUP, TASKS, Registry
from ..world.processors import DRIVER_TYPES
from .collisions import check_collision_constraint
from .context import CheckContext
from .controllers import cascade_controllers, mission_controllers
from .parameters import Subject, check_body, check_parameters

_SINGLE = ((ast.MissionHeader, "mission header"), (ast.LibraryHeader, "library header"),
           (ast.WorldDecl, "world"),
           (ast.ControllerDecl, "controller"), (ast.StartDecl, "start"))


def collect_symbols(ctx: CheckContext, mission: ast.Mission) -> None:
    """Record tasks, constraints, states and events (declared or emitted); report
    duplicate names."""
    symbols = ctx.symbols
    declared: dict = {}
    for event in mission.of_type(ast.EventDecl):
        if event.name.text in declared:
            _duplicate(ctx, "event", event.name, declared[event.name.text])
        declared.setdefault(event.name.text, event.name)
    symbols.events.update(declared)
    for decl in mission.tasks + mission.constraints:
        first = symbols.tasks.get(decl.name.text) or symbols.constraints.get(decl.name.text)
        if first is not None:
            _duplicate(ctx, "task or constraint", decl.name, first.name)
            continue
        table = symbols.tasks if isinstance(decl, ast.TaskDecl) else symbols.constraints
        table[decl.name.text] = decl
    for state in mission.states:
        symbols.states.setdefault(state.name.text, state)
    machines = [mission.machine] + [b.machine for b in mission.behaviors]
    symbols.events.update(e.text for m in machines for e in emitted(m))
    for name in set(symbols.tasks) | set(symbols.constraints):
        if name in declared:
            ctx.error("duplicate-name", f"event '{name}' has the name of a task or "
                      "constraint", declared[name].span, "give it a name of its own")


def emitted(machine: ast.Machine) -> list[ast.Name]:
    """The events that ``emit`` actions of a machine raise, at any depth."""
    found = []
    for item in machine.items:
        if isinstance(item, ast.Transition):
            found += [a.event for a in item.actions if isinstance(a, ast.Emit)]
            continue
        if not isinstance(item, ast.StateDecl):
            continue
        for part in item.parts:
            actions = part.actions
            found += [a.event for a in actions if isinstance(a, ast.Emit)]
        for region in item.regions:
            if region.machine is not None:
                found += emitted(region.machine)
    return found


def _duplicate(ctx: CheckContext, what: str, name: ast.Name, first: ast.Name) -> None:
    ctx.error("duplicate-name", f"{what} '{name.text}' is already declared", name.span,
              f"first declared at {ctx.where(first.span)}")


def check_header(ctx: CheckContext, mission: ast.Mission) -> None:
    """One mission header, world, controller and start at most; a header and a world."""
    for node_type, what in _SINGLE:
        items = mission.of_type(node_type)
        for extra in items[1:]:
            ctx.error("duplicate-declaration", f"a second {what} declaration", extra.span,
                      f"the first is at line {items[0].span.line}")
    if mission.first(ast.LibraryHeader) is not None:
        return
    if mission.first(ast.MissionHeader) is None:
        ctx.error("missing-declaration", "the file does not start with a mission header",
                  _first_line(mission), "begin with: mission NAME \"what it does\"")
    if mission.first(ast.WorldDecl) is None:
        ctx.error("missing-declaration", "the mission names no world", _first_line(mission),
                  "add: world \"FILE.yaml\" (relative to the mission, then the robots path)")
    if not mission.states:
        ctx.error("missing-declaration", "the mission declares no state",
                  _first_line(mission), "add: state NAME { ... } and a final state")


def _first_line(mission: ast.Mission) -> Span:
    """Where a missing declaration is reported: the start of the first item."""
    first = mission.items[0].span if mission.items else None
    line = first.line if first is not None and first.line > 0 else 1
    return Span.point(line)


def check_controller(ctx: CheckContext, mission: ast.Mission) -> None:
    """The named controller is a qp_controller of the world, or the world has one, or
    its controllers can run cascaded (see :mod:`.controllers`)."""
    if not ctx.world.known:
        return
    names = ctx.world.controller_names()
    declared = mission.first(ast.ControllerDecl)
    if declared is not None:
        if declared.name.text not in names:
            processors = ctx.world.world.processors
            extra = (f"'{declared.name.text}' is a {processors[declared.name.text].type} "
                     "processor, not a qp_controller"
                     if declared.name.text in processors else
                     "controllers: " + (", ".join(names) or "none"))
            ctx.unknown("unknown-controller", "controller", declared.name, names, extra)
    else:
        world = mission.first(ast.WorldDecl)
        span = world.path.span if world else None
        if not names:
            ctx.error("missing-controller", "the world has no qp_controller processor",
                      span, "add one under processors: in the world file")
        elif len(names) > 1 and not cascade_controllers(ctx.world):
            ctx.error("missing-controller", "the world has several controllers: "
                      + ", ".join(names), span, "choose one with: controller NAME "
                      "(controllers on disjoint joint groups run cascaded when the mission "
                      "names none)")
    _check_drivers(ctx, mission)


def _check_drivers(ctx: CheckContext, mission: ast.Mission) -> None:
    """Each controller the mission runs has a driver on its joint group (the one its
    ``driver:`` option names, or the only one there); cascaded controllers have no
    ``mujoco`` driver (one physics cannot be split between threads)."""
    processors = ctx.world.world.processors
    controllers = [name for name in mission_controllers(ctx.world, mission)
                   if name in ctx.world.controller_names()]
    drivers = {name: processor.options.get("joint_group")
               for name, processor in processors.items() if processor.type in DRIVER_TYPES}
    declared = mission.first(ast.ControllerDecl) or mission.first(ast.WorldDecl)
    span = declared.name.span if isinstance(declared, ast.ControllerDecl) else (
        declared.path.span if declared else None)
    for name in controllers:
        processor = processors[name]
        driver = processor.driver
        if driver is not None:
            if len(controllers) > 1 and processors[driver].type == "mujoco":
                ctx.error("missing-driver", f"the controllers run cascaded and the driver "
                          f"'{driver}' of '{name}' is a mujoco one", span,
                          "one physics cannot be split between the threads of a cascade: "
                          "run one controller on the physics world (controller NAME)")
            continue
        group = processor.options.get("joint_group")
        found = ("the world's driver processors: " + ", ".join(
            f"{driver} on '{on}'" for driver, on in drivers.items()) if drivers
                 else "the world has no driver processor")
        ctx.error("missing-driver", f"no driver for the controller '{name}': no driver "
                  f"processor drives its joint group '{group}'", span,
                  f"{found}; add one on '{group}' (simulated, loopback or mujoco)")


def check_declarations(ctx: CheckContext, mission: ast.Mission) -> None:
    """Types, arguments and parameters of every task and constraint."""
    for decl in mission.tasks:
        _check_declaration(ctx, decl, TASKS, "unknown-task-type")
        if decl.kind.text == "body_force" and len(decl.arguments) == 1:
            check_sensed(ctx, decl.arguments[0])
    for decl in mission.constraints:
        _check_declaration(ctx, decl, CONSTRAINTS, "unknown-constraint-type")


def check_sensed(ctx: CheckContext, body: ast.Name) -> bool:
    """Whether a force sensor measures ``body`` (reported when the world has none on
    it)."""
    sensed = ctx.world.sensed_bodies()
    if not ctx.world.known or not ctx.world.has_body(body.text):
        return True
    if body.text in sensed:
        if ctx.world.measures_wrenches:
            return True
        ctx.error("no-sensor", f"the force sensor on '{body.text}' never has a reading: "
                  "the world's drivers measure no wrench", body.span,
                  "a simulated driver measures none: run the mission on a world with a "
                  "mujoco driver or a loopback robot that reports it (run --world VARIANT)")
        return False
    ctx.error("no-sensor", f"'{body.text}' has no force sensor", body.span,
              "add one to the world: processors: {NAME: {type: force_sensor, options: "
              f"{{body: {body.text}}}}}}}" + (f" (sensed: {', '.join(sensed)})" if sensed
                                             else ""))
    return False


def subject_of(ctx: CheckContext, decl) -> Subject | None:
    """The subject of a declaration whose type is known, else ``None``."""
    registry = TASKS if isinstance(decl, ast.TaskDecl) else CONSTRAINTS
    kind = registry.get(decl.kind.text)
    if kind is None:
        return None
    joints = None
    if kind.subject == JOINT_GROUP and len(decl.arguments) == 1:
        joints = ctx.world.joints(decl.arguments[0].text)
    return Subject(kind, joints)


def _check_declaration(ctx: CheckContext, decl, registry: Registry, code: str) -> None:
    kind = registry.get(decl.kind.text)
    if kind is None:
        ctx.unknown(code, registry.family, decl.kind, registry.names(),
                    f"{registry.family}s: {', '.join(registry.names())}")
        return
    if kind.subject == COLLISION_SETS:
        check_collision_constraint(ctx, decl, kind)
        return
    subject_word = "joint group" if kind.subject == JOINT_GROUP else "body"
    if len(decl.arguments) != 1:
        ctx.error("wrong-arguments", f"{kind.name} takes one {subject_word}, "
                  f"not {len(decl.arguments)}", decl.kind.span,
                  f"write {kind.name}({subject_word.upper().replace(' ', '_')})")
        return
    argument = decl.arguments[0]
    if kind.subject == JOINT_GROUP:
        if not ctx.world.has_joints(argument.text):
            ctx.unknown("unknown-joint-group", "joint group", argument,
                        ctx.world.joint_names())
            return
    elif not check_body(ctx, argument):
        return
    given = [(p.name, p.value) for p in decl.parameters]
    owner = f"{'task' if isinstance(decl, ast.TaskDecl) else 'constraint'} '{decl.name.text}'"
    numbers = check_parameters(ctx, given, kind, subject_of(ctx, decl), owner,
                               decl.name.span)
    ordered = {name for pair in kind.ordered for name in pair}
    ctx.declared.setdefault(decl.name.text, {k: v for k, v in numbers.items()
                                             if k in ordered})
