"""From a compiled mission to a running one: the controller with the mission's tasks
and constraints, and the :class:`Program` of closures the runner executes."""

from __future__ import annotations

import operator

from ..compile import spec as s
from ..control import Controller, make_feedback_loop, make_interpolator
from .program import Clause, Program, StateProgram
from .targets import control_target

_COMPARE = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}


def build_controller(mission: s.MissionSpec, world, kinematics, **overrides) -> Controller:
    """The mission's controller processor with its constraints (enabled) and tasks
    (disabled), reading poses from ``kinematics``. ``overrides``: ``solver``,
    ``hierarchy``, ``time_step`` (``None`` keeps the world's)."""
    options = {k: v for k, v in overrides.items() if v is not None}
    controller = Controller.from_world(world, mission.controller, kinematics=kinematics,
                                       **options)
    for constraint in mission.constraints.values():
        parameters = {k: v for k, v in constraint.parameters.items() if v is not None}
        controller.add_constraint(constraint.type, constraint.name,
                                  constraint.joint_group or constraint.body, **parameters)
    for spec in mission.tasks.values():
        parameters = {
            "interpolator": make_interpolator(spec.interpolator.kind,
                                              **_scalars(spec.interpolator.parameters)),
            "feedback": make_feedback_loop(spec.feedback.kind, **spec.feedback.parameters),
            "priority": spec.priority, "weight": spec.weight}
        if spec.reference is not None:
            parameters["reference"] = spec.reference
        task = controller.add_task(spec.type, spec.name, spec.joint_group or spec.body,
                                   **parameters)
        if spec.gain is not None:
            task.gain = spec.gain
        task.target = control_target(task, spec.target)
    return controller


def _scalars(parameters: dict) -> dict:
    """One-value tuples (a scalar broadcast over the dofs) passed as plain numbers."""
    return {k: v[0] if isinstance(v, tuple) and len(v) == 1 else v
            for k, v in parameters.items()}


def build_program(mission: s.MissionSpec) -> Program:
    """Closures for every state's actions and clauses, built once."""
    states = {}
    for name, state in mission.states.items():
        own = [t for t in state.transitions if not t.guard]
        states[name] = StateProgram(
            name, state.final, state.outcome or "success",
            [action(a) for a in state.enter], [action(a) for a in state.during],
            [action(a) for a in state.exit], [clause(t) for t in own])
    return Program(states, [clause(t) for t in mission.guards], mission.start)


def clause(transition: s.TransitionSpec) -> Clause:
    return Clause(condition(transition.condition), transition.target, transition.text,
                  _uses_failure(transition.condition))


def _uses_failure(spec) -> bool:
    if isinstance(spec, s.ControllerFailedCondition):
        return True
    if isinstance(spec, s.NotCondition):
        return _uses_failure(spec.operand)
    if isinstance(spec, (s.AllCondition, s.AnyCondition)):
        return any(_uses_failure(o) for o in spec.operands)
    return False


def condition(spec):
    """A function of the runner that tells whether ``spec`` holds this cycle."""
    if isinstance(spec, s.ReachedCondition):
        return lambda runner, name=spec.task: runner.controller.task(name).reached
    if isinstance(spec, s.ControllerFailedCondition):
        return lambda runner: runner.failed
    if isinstance(spec, s.EventCondition):
        return lambda runner, event=spec.event: event in runner.events_now
    if isinstance(spec, s.NotCondition):
        operand = condition(spec.operand)
        return lambda runner: not operand(runner)
    if isinstance(spec, s.AllCondition):
        operands = [condition(o) for o in spec.operands]
        return lambda runner: all(o(runner) for o in operands)
    if isinstance(spec, s.AnyCondition):
        operands = [condition(o) for o in spec.operands]
        return lambda runner: any(o(runner) for o in operands)
    measure, compare, value = _measure(spec.measure), _COMPARE[spec.operator], spec.value
    return lambda runner: compare(measure(runner), value)


def _measure(spec):
    if isinstance(spec, s.ElapsedMeasure):
        return lambda runner: runner.elapsed
    if isinstance(spec, s.TimeMeasure):
        return lambda runner: runner.time
    if isinstance(spec, s.DistanceMeasure):
        return lambda runner, a=spec.first, b=spec.second: runner.kinematics.distance(a, b)
    return lambda runner, name=spec.task, field=spec.field: getattr(
        runner.controller.task(name), field)


def action(spec):
    """A function of the runner that performs ``spec``."""
    if isinstance(spec, s.EnableAction):
        return lambda runner, names=spec.names: _switch(runner, names, True)
    if isinstance(spec, s.DisableAction):
        return lambda runner, names=spec.names: _switch(runner, names, False)
    if isinstance(spec, s.ResetAction):
        return lambda runner, names=spec.names: [runner.controller.task(n).reset()
                                                 for n in names]
    if isinstance(spec, s.SetTargetAction):
        return lambda runner, name=spec.task, target=spec.target: _set_target(
            runner, name, target)
    if isinstance(spec, s.SetParameterAction):
        return lambda runner, spec=spec: _set_parameter(runner, spec)
    if isinstance(spec, s.AttachAction):
        return lambda runner, body=spec.body, parent=spec.parent: runner.attach(body, parent)
    if isinstance(spec, s.DetachAction):
        return lambda runner, body=spec.body: runner.detach(body)
    if isinstance(spec, s.EmitAction):
        return lambda runner, event=spec.event: runner.emit(event)
    return lambda runner, text=spec.text: runner.log(text)


def _owner(runner, name: str):
    controller = runner.controller
    if name in {t.name for t in controller.tasks()}:
        return controller.task(name)
    return controller.constraint(name)


def _switch(runner, names, enabled: bool) -> None:
    for name in names:
        owner = _owner(runner, name)
        if enabled:
            owner.enable()
        else:
            owner.disable()


def _set_target(runner, name: str, target) -> None:
    task = runner.controller.task(name)
    task.target = control_target(task, target)


def _set_parameter(runner, spec: s.SetParameterAction) -> None:
    setattr(_owner(runner, spec.owner), spec.parameter, spec.value)
