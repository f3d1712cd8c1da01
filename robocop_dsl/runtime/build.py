"""From a compiled mission to a running one: the controller with the mission's tasks
and constraints, and the :class:`Program` of closures the runner executes.

Actions are ``action(runner)``; clause tests are ``test(runner, owner)`` with ``owner``
the :class:`~robocop_dsl.runtime.statechart.Activation` of the state owning the clause
(``elapsed`` counts from its entry); they read the runner's ``time``, ``cycle``,
``failed``, ``kinematics``, ``controller`` and ``chart`` (the
:class:`~robocop_dsl.runtime.statechart.Statechart`: finals, visits, events).

In a cascade (see :mod:`robocop_dsl.runtime.cascade`) each controller gets the tasks
and constraints it runs, and the program, executed by the thread of the first
controller, reaches the others through a ``remote`` object: ``is_local(name)``,
``send(name, action)`` (run ``action`` in the thread of the controller that runs task
or constraint ``name``, on an object whose ``controller`` is that controller) and
``status(task)`` (its latest :class:`~robocop_dsl.runtime.cascade.TaskStatus`)."""

from __future__ import annotations

import operator

from ..compile import spec as s
from ..compile import variables as v
from ..compile.state_graph import join
from ..control import Controller, make_feedback_loop, make_interpolator
from .clearance import Clearance
from .program import Clause, MachineProgram, Program, StateProgram
from .targets import control_target
from .variables import evaluator, log_text, resolved

_COMPARE = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}


def build_controller(mission: s.MissionSpec, world, kinematics, processor: str | None = None,
                     **overrides) -> Controller:
    """A controller processor of the mission (default the one running the state machine)
    with the constraints and tasks it runs, enabled as declared (constraints by default,
    tasks declared ``enabled = true``), reading poses from ``kinematics``. ``overrides``: ``solver``, ``hierarchy``, ``time_step`` (``None``
    keeps the world's)."""
    options = {k: v for k, v in overrides.items() if v is not None}
    processor = processor or mission.controller
    controller = Controller.from_world(world, processor, kinematics=kinematics, **options)
    mine = (lambda spec: spec.controller in (None, processor))
    for constraint in filter(mine, mission.constraints.values()):
        parameters = {k: v for k, v in constraint.parameters.items() if v is not None}
        added = controller.add_constraint(constraint.type, constraint.name,
                                          constraint.joint_group or constraint.body,
                                          **parameters)
        added.enabled = constraint.enabled
    for spec in filter(mine, mission.tasks.values()):
        parameters = {"priority": spec.priority, "weight": spec.weight, **spec.options}
        if spec.type == "body_force":
            parameters["gain"] = spec.gain
        else:
            parameters["interpolator"] = make_interpolator(
                spec.interpolator.kind, **_scalars(spec.interpolator.parameters))
            parameters["feedback"] = make_feedback_loop(spec.feedback.kind,
                                                        **spec.feedback.parameters)
        if spec.tolerance:
            parameters["tolerance"] = spec.tolerance
        if spec.reference is not None and spec.type != "body_force":
            parameters["reference"] = spec.reference
        task = controller.add_task(spec.type, spec.name, spec.joint_group or spec.body,
                                   **parameters)
        if spec.gain is not None and spec.type != "body_force":
            task.gain = spec.gain
        task.target = control_target(task, spec.target)
        if spec.enabled:
            task.enable()
    return controller


def _scalars(parameters: dict) -> dict:
    """One-value tuples (a scalar broadcast over the dofs) passed as plain numbers."""
    return {k: v[0] if isinstance(v, tuple) and len(v) == 1 else v
            for k, v in parameters.items()}


def build_program(mission: s.MissionSpec, remote=None) -> Program:
    """Closures for every state's actions and clauses, built once; ``remote`` reaches
    the tasks and constraints of the other controllers of a cascade (see above)."""
    return Program(build_machine(mission.machine, remote), mission.variables)


def build_machine(machine: s.MachineSpec, remote=None) -> MachineProgram:
    """The :class:`MachineProgram` of ``machine`` and of every machine nested in it."""
    states = {name: _state(state, machine.path, remote)
              for name, state in machine.states.items()}
    return MachineProgram(machine.path, states, machine.start,
                          [clause(t, remote) for t in machine.guards], machine.region)


def _state(state: s.StateSpec, machine: str, remote) -> StateProgram:
    return StateProgram(
        state.name, state.final, state.outcome or "success",
        _actions(state.enter, remote), _actions(state.during, remote),
        _actions(state.exit, remote),
        [clause(t, remote) for t in state.transitions if not t.guard],
        state.path or join(machine, state.name), machine,
        [build_machine(m, remote) for m in state.machines], state.parallel)


def _actions(specs, remote) -> list:
    return [action(a, remote) for a in specs]


def clause(transition: s.TransitionSpec, remote=None) -> Clause:
    return Clause(condition(transition.condition, remote), transition.target,
                  transition.text, _uses_failure(transition.condition),
                  _actions(transition.actions, remote))


def _uses_failure(spec) -> bool:
    if isinstance(spec, s.ControllerFailedCondition):
        return True
    if isinstance(spec, s.NotCondition):
        return _uses_failure(spec.operand)
    if isinstance(spec, (s.AllCondition, s.AnyCondition)):
        return any(_uses_failure(o) for o in spec.operands)
    return False


def _task_reader(name: str, remote):
    """A function of the runner that gives task ``name``, or for a task of another
    controller of a cascade its latest status."""
    if remote is not None and not remote.is_local(name):
        return lambda runner: remote.status(name)
    return lambda runner: runner.controller.task(name)


def condition(spec, remote=None):
    """A function ``test(runner, owner)`` that tells whether ``spec`` holds this cycle
    for a clause whose owner state's entry is ``owner`` (an
    :class:`~robocop_dsl.runtime.statechart.Activation`)."""
    if isinstance(spec, s.ReachedCondition):
        task = _task_reader(spec.task, remote)
        return lambda runner, owner: task(runner).reached
    if isinstance(spec, s.InterpolatedCondition):
        task = _task_reader(spec.task, remote)
        return lambda runner, owner: task(runner).interpolated
    if isinstance(spec, s.ControllerFailedCondition):
        return lambda runner, owner: runner.failed
    if isinstance(spec, s.EventCondition):
        return lambda runner, owner, event=spec.event: runner.chart.seen(event, owner,
                                                                          runner.cycle)
    if isinstance(spec, s.FinalCondition):
        return lambda runner, owner, c=spec: runner.chart.in_final(c.state, c.final, c.region)
    if isinstance(spec, s.DoneCondition):
        return lambda runner, owner, path=spec.state: runner.chart.done(path)
    if isinstance(spec, s.NotCondition):
        operand = condition(spec.operand, remote)
        return lambda runner, owner: not operand(runner, owner)
    if isinstance(spec, s.AllCondition):
        operands = [condition(o, remote) for o in spec.operands]
        return lambda runner, owner: all(o(runner, owner) for o in operands)
    if isinstance(spec, s.AnyCondition):
        operands = [condition(o, remote) for o in spec.operands]
        return lambda runner, owner: any(o(runner, owner) for o in operands)
    if isinstance(spec, v.ContactCondition):
        return lambda runner, owner, a=spec.first, b=spec.second: runner.contact(a, b)
    read, compare = measure(spec.measure, remote), _COMPARE[spec.operator]
    if isinstance(spec.value, v.VarValue):
        value = evaluator(spec.value)
        return lambda runner, owner: compare(read(runner, owner), value(runner, owner))
    return lambda runner, owner, value=spec.value: compare(read(runner, owner), value)


def measure(spec, remote=None):
    """A function ``measure(runner, owner)`` giving the value of ``spec`` [SI]."""
    if isinstance(spec, (v.VarValue, v.PositionMeasure, v.WrenchMeasure)):
        return evaluator(spec)
    if isinstance(spec, s.ElapsedMeasure):
        return lambda runner, owner: round(runner.time - owner.time, 9)
    if isinstance(spec, s.VisitsMeasure):
        return lambda runner, owner, path=spec.state: runner.chart.visits(path)
    if isinstance(spec, s.TimeMeasure):
        return lambda runner, owner: runner.time
    if isinstance(spec, s.DistanceMeasure):
        return lambda runner, owner, a=spec.first, b=spec.second: \
            runner.kinematics.distance(a, b)
    if isinstance(spec, s.ClearanceMeasure):
        return lambda runner, owner, clearance=Clearance(spec.first, spec.second): \
            clearance(runner.kinematics)
    task = _task_reader(spec.task, remote)
    return lambda runner, owner, field=spec.field: getattr(task(runner), field)


def _routed(name: str, remote, act):
    """``act(runner)`` run here, or in the thread of the cascade's controller that runs
    task or constraint ``name``."""
    if remote is None or remote.is_local(name):
        return act
    return lambda runner: remote.send(name, act)


def _each(names, remote, act):
    """``act(runner, name)`` for each name, each where its controller runs."""
    parts = [_routed(n, remote, lambda runner, n=n: act(runner, n)) for n in names]
    return lambda runner: [part(runner) for part in parts]


def action(spec, remote=None):
    """A function of the runner that performs ``spec``."""
    if isinstance(spec, s.EnableAction):
        return _each(spec.names, remote, lambda runner, n: _switch(runner, n, True))
    if isinstance(spec, s.DisableAction):
        return _each(spec.names, remote, lambda runner, n: _switch(runner, n, False))
    if isinstance(spec, s.ResetAction):
        return _each(spec.names, remote, lambda runner, n: runner.controller.task(n).reset())
    if isinstance(spec, s.SetTargetAction):
        return _routed(spec.task, remote, lambda runner, name=spec.task, target=spec.target:
                       _set_target(runner, name, target))
    if isinstance(spec, s.SetParameterAction):
        return _routed(spec.owner, remote, lambda runner, spec=spec: _set_parameter(runner, spec))
    if isinstance(spec, s.AttachAction):
        return lambda runner, body=spec.body, parent=spec.parent: runner.attach(body, parent)
    if isinstance(spec, s.DetachAction):
        return lambda runner, body=spec.body: runner.detach(body)
    if isinstance(spec, s.EmitAction):
        return lambda runner, event=spec.event: runner.emit(event)
    if isinstance(spec, v.SetVarAction):
        value = evaluator(spec.value, remote)
        return lambda runner, name=spec.name: runner.assign(name, value(runner, None))
    if spec.fields:
        return lambda runner, log=spec: runner.log(log_text(log, runner))
    return lambda runner, text=spec.text: runner.log(text)


def _owner(runner, name: str):
    controller = runner.controller
    if name in {t.name for t in controller.tasks()}:
        return controller.task(name)
    return controller.constraint(name)


def _switch(runner, name: str, enabled: bool) -> None:
    owner = _owner(runner, name)
    if enabled:
        owner.enable()
    else:
        owner.disable()


def _set_target(runner, name: str, target) -> None:
    task = runner.controller.task(name)
    task.target = control_target(task, resolved(target, runner))


def _set_parameter(runner, spec: s.SetParameterAction) -> None:
    setattr(_owner(runner, spec.owner), spec.parameter, spec.value)
