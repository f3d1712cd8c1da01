"""The kinematic QP whole-body controller: tasks and constraints to joint velocities."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .constraints import CONSTRAINTS, Constraint
from .exceptions import (DuplicateName, InvalidParameter, PartFailed, UnknownKind,
                         UnknownName)
from .hierarchy import Hierarchy, Objective
from .kinematics import Kinematics
from .parameters import scalar_parameter
from .results import ControlResult, Timings
from .solvers import QuadraticProgram, braking_solver, level_solvers, make_solver
from .state import ControlState, resolve_group
from .tasks import TASKS, Task
from ..safety.braking import BrakingProgram
from ..safety.joint_box import JointBox
from ..safety.limits import JointLimits, joint_limits
from ..safety.relaxation import Relaxer, RowGroup
from ..world.processors import option_default

HIERARCHIES = ("strict", "weighted")


@dataclass
class _Plan:
    """What stays fixed while no task or constraint is enabled, disabled or re-prioritised."""

    revision: int
    tasks: list[tuple[Task, slice]]
    hierarchy: Hierarchy
    full_box: Constraint | None
    boxes: list[Constraint]
    rows: list[tuple[Constraint, np.ndarray, np.ndarray, np.ndarray]]
    """Each row constraint with its rows of the QP's ``C``, ``l`` and ``u`` (views)."""
    limits: JointLimits
    box: JointBox
    groups: list[RowGroup]
    """Each row constraint's rows, and whether a relaxation may add slack to them."""
    braking: BrakingProgram
    hard: tuple[np.ndarray, np.ndarray]
    """The cycle's box before the acceleration limits [rad/s or m/s]."""
    weights: list
    """Each task's weight array last written into the QP (rewritten when the task's
    weight is another array)."""


class Controller:
    """Computes, every period, the joint velocities of a group that best realise the
    enabled tasks under the enabled constraints.

    The runtime owns the state: each cycle it passes the whole model's configuration
    to :meth:`compute` and integrates or sends the returned command. The URDF's
    velocity limits bound every command, with or without a ``joint_kinematic``
    constraint.

    Args:
        world: The world (its ``model``, bodies and joint groups).
        joint_group: The controlled joint group; the command has one entry per joint.
        time_step: Control period [s].
        solver: ``"auto"`` (one backend per QP, see
            :mod:`robocop_dsl.control.solvers.choice`), ``"daqp"``, ``"proxqp"`` (both
            reused and warm-started) or a qpsolvers backend name.
        hierarchy: ``"strict"`` (one QP per priority level, see
            :mod:`robocop_dsl.control.hierarchy`) or ``"weighted"`` (one QP, weights).
        damping: Weight of ``|dq|^2`` in every QP [-], keeps them strictly convex.
        lm_damping: Levenberg-Marquardt damping [per task unit^2]: each level also
            weighs ``|dq|^2`` by this times its position tasks' weighted squared
            tracking errors, which ends the chatter toward targets out of reach (see
            :mod:`robocop_dsl.control.hierarchy`).
        kinematics: A :class:`Kinematics` to share with the runtime; default a new one.

    Raises:
        UnknownName: the joint group does not exist.
        UnknownSolver: the solver is not installed.
        InvalidParameter: invalid time step, hierarchy or damping.
    """

    def __init__(self, world, joint_group: str, time_step: float, solver: str = "auto",
                 hierarchy: str = "strict", *,
                 damping: float = option_default("qp_controller", "damping"),
                 lm_damping: float = option_default("qp_controller", "lm_damping"),
                 kinematics: Kinematics | None = None):
        if hierarchy not in HIERARCHIES:
            raise InvalidParameter("controller", "hierarchy", hierarchy,
                                   " or ".join(HIERARCHIES))
        self.time_step = scalar_parameter("controller", "time_step", time_step, minimum=0.0,
                                          strict=True)
        self.damping = scalar_parameter("controller", "damping", damping, minimum=0.0,
                                        strict=True)
        self.lm_damping = scalar_parameter("controller", "lm_damping", lm_damping,
                                           minimum=0.0)
        self.hierarchy = hierarchy
        self.solver = solver
        make_solver(solver)
        self.world = world
        self.kinematics = kinematics if kinematics is not None else Kinematics(world)
        group = resolve_group(world, joint_group)
        self.state = ControlState(self.kinematics, group, self.time_step)
        self._tasks: dict[str, Task] = {}
        self._constraints: dict[str, Constraint] = {}
        self._auto_enable: bool | None = None
        self._cached_plan: _Plan | None = None
        self.failed = False
        self.result: ControlResult | None = None
        self.problems: list[QuadraticProgram] = []
        self._relaxer = Relaxer()
        self._relaxing = False

    @classmethod
    def from_world(cls, world, processor: str | None = None, **overrides) -> "Controller":
        """A controller configured by a ``qp_controller`` processor of the world.

        Args:
            world: The world.
            processor: The processor's name; default the world's only controller.
            **overrides: Constructor arguments replacing the processor's options.
        """
        names = world.controller_names()
        if processor is None and len(names) == 1:
            processor = names[0]
        if processor not in names:
            raise UnknownName("qp_controller processor", str(processor), names)
        options = dict(world.processors[processor].options)
        options.update(overrides)
        return cls(world, options.pop("joint_group"), options.pop("time_step"), **options)

    @property
    def joint_group(self):
        """The controlled joint group."""
        return self.state.group

    @property
    def sensors(self):
        """Where force tasks read their body's wrench: an object with ``wrench(body) ->
        [fx, fy, fz, tx, ty, tz]`` [N, N m], what the body exerts on the environment in
        the world frame (a runner gives its
        :class:`~robocop_dsl.runtime.sensors.Sensors`); ``None`` until set."""
        return self.state.sensors

    @sensors.setter
    def sensors(self, sensors) -> None:
        self.state.sensors = sensors

    @property
    def limits(self) -> JointLimits | None:
        """The joint limits table of the latest cycle (the world's met with the enabled
        ``joint_kinematic`` constraints'), ``None`` before the first cycle."""
        plan = self._cached_plan
        return None if plan is None else plan.limits

    def set_auto_enable(self, enabled: bool) -> None:
        """Enable (or not) tasks and constraints as they are added.

        Until called, constraints start enabled and tasks disabled.
        """
        self._auto_enable = bool(enabled)

    def add_task(self, kind: str, name: str, body_or_group: str, **parameters) -> Task:
        """Add a task of a registered ``kind`` on a body or joint group.

        Args:
            kind: ``joint_position``, ``joint_velocity``, ``body_position``,
                ``body_orientation``, ``body_pose``, ``body_velocity``, ``gaze`` or
                ``body_force`` (which reads :attr:`sensors`).
            name: Unique task name.
            body_or_group: The body (body tasks) or joint group (joint tasks).
            **parameters: ``target``, ``reference``, ``interpolator``, ``feedback``,
                ``weight``, ``priority``, ``gain``.

        Raises:
            UnknownKind, DuplicateName, UnknownName, InvalidParameter.
        """
        if kind not in TASKS:
            raise UnknownKind("task", kind, TASKS)
        if name in self._tasks:
            raise DuplicateName("task", name)
        task = TASKS[kind](name, self.state, body_or_group, **parameters)
        if self._auto_enable:
            task.enable()
        self._tasks[name] = task
        self.state.revision += 1
        return task

    def add_constraint(self, kind: str, name: str, body_or_group: str,
                       **parameters) -> Constraint:
        """Add a constraint of a registered ``kind`` (``joint_kinematic``,
        ``body_velocity``) on a joint group or body.

        Raises:
            UnknownKind, DuplicateName, UnknownName, InvalidParameter.
        """
        if kind not in CONSTRAINTS:
            raise UnknownKind("constraint", kind, CONSTRAINTS)
        if name in self._constraints:
            raise DuplicateName("constraint", name)
        constraint = CONSTRAINTS[kind](name, self.state, body_or_group, **parameters)
        constraint.enabled = self._auto_enable is not False
        self._constraints[name] = constraint
        return constraint

    def remove_task(self, name: str) -> None:
        """Remove a task."""
        self.task(name)
        del self._tasks[name]
        self.state.revision += 1

    def remove_constraint(self, name: str) -> None:
        """Remove a constraint."""
        self.constraint(name)
        self._constraints.pop(name).release()
        self.state.revision += 1

    def task(self, name: str) -> Task:
        """The task called ``name``; raises :class:`UnknownName` listing the tasks."""
        try:
            return self._tasks[name]
        except KeyError:
            raise UnknownName("task", name, self._tasks) from None

    def constraint(self, name: str) -> Constraint:
        """The constraint called ``name``; raises :class:`UnknownName` listing them."""
        try:
            return self._constraints[name]
        except KeyError:
            raise UnknownName("constraint", name, self._constraints) from None

    def tasks(self) -> tuple[Task, ...]:
        """Every task, in the order added."""
        return tuple(self._tasks.values())

    def constraints(self) -> tuple[Constraint, ...]:
        """Every constraint, in the order added."""
        return tuple(self._constraints.values())

    def reset(self) -> None:
        """Forget the previous command and warm starts; tasks restart at the next cycle."""
        self.state.previous_command = np.zeros(self.state.dofs)
        self.state.velocity = np.zeros(self.state.dofs)
        for task in self._tasks.values():
            task.reset()
            task.feedback_loop().reset()
        self._cached_plan = None
        self._relaxing = False
        self.failed = False
        self.result = None

    def update_state(self, q: np.ndarray, dq: np.ndarray | None = None) -> None:
        """Make ``q`` (nq) and ``dq`` (nv, optional) the state that errors are read at."""
        self.kinematics.update(np.asarray(q, dtype=float))
        state = self.state
        state.velocity = (state.previous_command if dq is None
                          else np.asarray(dq, dtype=float)[state.v_indices])

    def prepare(self, q: np.ndarray, dq: np.ndarray | None = None) -> None:
        """Do ahead what the next :meth:`compute` at ``q`` (nq) and ``dq`` (nv) would do
        first: plan the enabled tasks and constraints (levels, QP buffers, solvers) and
        find the collision pairs within influence, so that the cycle itself starts warm
        (a run prepares before its first cycle). No task, interpolator or command
        changes; a state :meth:`compute` would refuse is left to it to report."""
        q = np.asarray(q, dtype=float)
        if self._check_state(q, dq) is None:
            self.update_state(q, dq)
            self._plan()

    def compute(self, q: np.ndarray, dq: np.ndarray | None = None) -> ControlResult:
        """One control cycle at configuration ``q`` (nq) and velocity ``dq`` (nv).

        ``dq`` defaults to the previous command. Never raises on bad numbers or an
        infeasible QP: a cycle whose constraints have no common command is relaxed
        (``status == "relaxed"``), one whose solver spent its iteration budget takes the
        braking QP's answer (``"solver_budget"``), both with ``solved=False``; only
        non-finite input or contradictory position limits give a zero command
        (``"no_solution"``).
        """
        start = time.perf_counter()
        plan = self._begin(q, dq, start)
        if isinstance(plan, ControlResult):
            return plan
        state = self.state
        hierarchy = plan.hierarchy
        jacobian, velocity, weight = hierarchy.jacobian, hierarchy.velocity, hierarchy.weight
        after_kinematics = time.perf_counter()
        objectives = []
        squared_errors = hierarchy.squared_errors if self.lm_damping else None
        weights = plan.weights
        for index, (task, rows) in enumerate(plan.tasks):
            if not task.target_is_finite():
                reason = _unbounded_reference(plan.tasks, objectives)
                return self._refuse(reason or f"target of {task.label} is not finite", start)
            task_jacobian, task_velocity = _part("task", task, task.compute_objective, state)
            task_weight = task.weight
            jacobian[rows] = task_jacobian
            velocity[rows] = task_velocity
            if task_weight is not weights[index]:
                weights[index] = task_weight
                weight[rows] = task_weight[:, None]
            if squared_errors is not None and task.positional:
                error = task.tracking_error
                squared_errors[index] = error.dot(error * task_weight)
            objectives.append(Objective(task.name, task_jacobian, task_velocity, task_weight))
        if not math.isfinite(velocity.dot(velocity)):  # one check for every task
            reason = _unbounded_reference(plan.tasks, objectives)
            if reason:
                return self._refuse(reason, start)
        after_tasks = time.perf_counter()
        relaxations = self._bounds(plan)
        after_constraints = time.perf_counter()
        command, level_results, more, exhausted = self._answer(plan, objectives)
        end = time.perf_counter()
        if command is None:
            return self._refuse("no QP solution (constraints infeasible or solver failure)",
                                start)
        relaxations += more
        status = "solver_budget" if exhausted else "relaxed" if relaxations else "solved"
        timings = Timings(after_kinematics - start, after_tasks - after_kinematics,
                          after_constraints - after_tasks, end - after_constraints,
                          end - start)
        return self._finish(ControlResult(command, status == "solved", level_results, timings,
                                          None, tuple(relaxations), status))

    def _begin(self, q, dq, start: float):
        """The cycle's plan at ``q`` and ``dq``, the kinematics updated; a refused
        :class:`ControlResult` when they are not finite or the position limits leave a
        joint no position."""
        q = np.asarray(q, dtype=float)
        reason = self._check_state(q, dq)
        if reason:
            return self._refuse(reason, start)
        self.update_state(q, dq)
        plan = self._plan()
        if plan.limits.conflict:
            return self._refuse(f"constraints have no common solution: {plan.limits.conflict}",
                                start)
        return plan

    def _check_state(self, q: np.ndarray, dq) -> str | None:
        model = self.kinematics.model
        if q.shape != (model.nq,):
            return f"configuration has shape {q.shape}, expected ({model.nq},)"
        if not math.isfinite(q.dot(q)):
            return "configuration is not finite"
        if dq is not None:
            dq = np.asarray(dq, dtype=float)
            if dq.shape != (model.nv,):
                return f"velocity has shape {dq.shape}, expected ({model.nv},)"
            if not math.isfinite(dq.dot(dq)):
                return "velocity is not finite"
        return None

    def _plan(self) -> _Plan:
        """The enabled tasks and constraints, levels and QP buffers (rebuilt on changes)."""
        plan = self._cached_plan
        if plan is not None and plan.revision == self.state.revision:
            return plan
        tasks = [task for task in self._tasks.values() if task.enabled]
        constraints = [c for c in self._constraints.values() if c.enabled]
        if self.hierarchy == "weighted" or not tasks:
            levels = [(0, list(range(len(tasks))))]
        else:
            by_priority: dict[int, list[int]] = {}
            for index, task in enumerate(tasks):
                by_priority.setdefault(task.priority, []).append(index)
            levels = sorted(by_priority.items())
        tables = [c for c in constraints if c.joint_limits() is not None]
        limits = joint_limits(self.state.group, tables)
        self.state.max_acceleration = limits.max_acceleration
        constraints = [c for c in constraints if c not in tables]
        everything = np.arange(self.state.dofs)
        boxes = [c for c in constraints if c.box_columns is not None]
        first = next((c for c in boxes if np.array_equal(c.box_columns, everything)), None)
        spans, count = [], 0
        for constraint in constraints:
            if constraint.box_columns is None:
                spans.append((constraint, slice(count, count + constraint.rows)))
                count += constraint.rows
        hierarchy = Hierarchy(levels, [task.name for task in tasks],
                              [task.dimension for task in tasks], self.state.dofs, count,
                              level_solvers(self.solver, [[tasks[index].dimension for index in
                                                           indices] for _, indices in levels],
                                            self.state.dofs), self.damping,
                              self.lm_damping)
        rows = [(constraint, hierarchy.C[span], hierarchy.l[span], hierarchy.u[span])
                for constraint, span in spans]
        groups = [RowGroup(constraint.label, span, constraint.kind == "body_velocity",
                           "m/s or rad/s") for constraint, span in spans]
        plan = _Plan(self.state.revision,
                     [(task, hierarchy.task_rows(index)) for index, task in enumerate(tasks)],
                     hierarchy, first, [c for c in boxes if c is not first], rows, limits,
                     JointBox(limits, self.time_step), groups,
                     BrakingProgram(hierarchy, braking_solver(self.solver)),
                     (np.zeros(self.state.dofs), np.zeros(self.state.dofs)),
                     [None] * len(tasks))
        self._cached_plan = plan
        return plan

    def _bounds(self, plan: _Plan) -> list:
        """Write the constraints' bounds and rows into the plan's QPs: the joint limits
        table as viable bounds (:class:`~robocop_dsl.safety.joint_box.JointBox`), the other
        box constraints, the rows, then the acceleration limits. Returns the
        acceleration limits relaxed where a joint's box does not meet them."""
        state = self.state
        hierarchy = plan.hierarchy
        lower, upper = plan.hard
        plan.box.write(state.group_positions, state.previous_command, lower, upper)
        if plan.full_box is not None:
            low, high = _part("constraint", plan.full_box, plan.full_box.compute_bounds, state)
            np.maximum(lower, low, out=lower)
            np.minimum(upper, high, out=upper)
        for constraint in plan.boxes:
            low, high = _part("constraint", constraint, constraint.compute_bounds, state)
            columns = constraint.box_columns
            lower[columns] = np.maximum(lower[columns], low)
            upper[columns] = np.minimum(upper[columns], high)
        for constraint, jacobian, low, high in plan.rows:
            _part("constraint", constraint, constraint.write_rows, state, jacobian, low, high)
        hierarchy.lower[:] = lower
        hierarchy.upper[:] = upper
        return plan.box.accelerations(state.previous_command, hierarchy.lower,
                                      hierarchy.upper, state.group.joints)

    def _answer(self, plan: _Plan, objectives: list[Objective]):
        """``(command, level results, relaxations, exhausted)`` of a cycle whose bounds are
        written: the hierarchy's answer. When it has none, the relaxation QP
        (:mod:`robocop_dsl.safety.relaxation`) tells whether the hard set has a common
        command: if not, the hierarchy's answer under the smallest relaxation; if so (or
        if the hierarchy still finds none), the solver did not find the answer within
        its budget (``exhausted``), and the braking QP answers. While the cycles before
        were relaxed, the relaxation QP comes first (the hard set likely has no common
        command still). ``command`` is ``None`` only when nothing, not even holding
        still, meets the constraints."""
        hierarchy = plan.hierarchy
        tried = not (self._relaxing or plan.rows
                     and np.count_nonzero(np.greater(hierarchy.l, hierarchy.u)))
        if tried:
            command, levels, self.problems = hierarchy.solve(objectives)
            if command is not None:
                return command, levels, [], False
        relaxed = self._relax(plan)
        if relaxed is None:
            return None, (), [], False
        fallback, relaxations = relaxed
        self._relaxing = bool(relaxations)
        if relaxations or not tried:
            command, levels, self.problems = hierarchy.solve(objectives)
            if command is not None:
                return command, levels, relaxations, False
        command = plan.braking.solve()
        return (fallback if command is None else command), (), relaxations, True

    def _braking_answer(self, plan: _Plan):
        """``(command, relaxations)`` of the braking QP over the written bounds."""
        command = plan.braking.solve()
        if command is not None:
            return command, []
        relaxed = self._relax(plan)
        if relaxed is None:
            return None, []
        fallback, relaxations = relaxed
        command = plan.braking.solve()
        return (fallback if command is None else command), relaxations

    def _relax(self, plan: _Plan):
        state = self.state
        return self._relaxer.relax(plan.braking.program, plan.hard, state.previous_command,
                                   plan.limits, state.time_step, plan.groups,
                                   state.group.joints)

    def brake(self, q: np.ndarray, dq: np.ndarray | None = None,
              previous: np.ndarray | None = None) -> ControlResult:
        """One cycle of a stop at ``q`` (nq): the velocity brought towards zero as fast
        as the acceleration limits allow, every enabled constraint held
        (:mod:`robocop_dsl.safety.braking`); tasks are not computed. The command is
        zero once at rest. ``previous``: the command [rad/s or m/s] sent last, when it
        is not this controller's last answer (a refused cycle answers zero; a caller
        that brakes instead did not send it)."""
        start = time.perf_counter()
        if previous is not None:
            self.state.previous_command = np.array(previous, dtype=float)
        plan = self._begin(q, dq, start)
        if isinstance(plan, ControlResult):
            return plan
        relaxations = self._bounds(plan)
        command, more = self._braking_answer(plan)
        if command is None:
            return self._refuse("no braking command meets the constraints", start)
        relaxations += more
        status = "relaxed" if relaxations else "solved"
        total = time.perf_counter() - start
        return self._finish(ControlResult(command, not relaxations, (), Timings(total=total),
                                          None, tuple(relaxations), status))

    def _refuse(self, reason: str, start: float) -> ControlResult:
        self._cached_plan = None
        total = time.perf_counter() - start
        return self._finish(ControlResult(np.zeros(self.state.dofs), False,
                                          timings=Timings(total=total), reason=reason,
                                          status="no_solution"))

    def _finish(self, result: ControlResult) -> ControlResult:
        self.state.previous_command = result.velocity
        self.failed = not result.solved
        self.result = result
        return result

    def __repr__(self) -> str:
        enabled_tasks = sum(task.enabled for task in self._tasks.values())
        enabled_constraints = sum(c.enabled for c in self._constraints.values())
        return (f"Controller(group={self.state.group.name!r}, dofs={self.state.dofs}, "
                f"time_step={self.time_step}, solver={self.solver!r}, "
                f"hierarchy={self.hierarchy!r}, tasks={enabled_tasks}/{len(self._tasks)} "
                f"enabled, constraints={enabled_constraints}/{len(self._constraints)} enabled)")


def _unbounded_reference(tasks: list[tuple[Task, slice]], objectives: list[Objective]):
    """Why the cycle is refused if one of ``objectives`` has a non-finite velocity (the
    first, in the order of ``tasks``), else ``None``."""
    for (task, _), objective in zip(tasks, objectives):
        if not math.isfinite(objective.velocity.dot(objective.velocity)):
            return f"reference of {task.label} is not finite"
    return None


def _part(role: str, part, method, state, *arguments):
    """``method(state, *arguments)`` of ``part``, a ``role`` (task or constraint);
    whatever it raises comes out as :class:`PartFailed` naming the part."""
    try:
        return method(state, *arguments)
    except Exception as error:  # named for whoever reports it
        raise PartFailed(f"{role} '{part.name}'", error) from error
