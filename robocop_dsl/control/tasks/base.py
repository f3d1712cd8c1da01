"""Abstract task: a desired motion of a body or joint group, as a QP objective.

A subclass implements two hooks, :meth:`Task.compute_value` (where the task is now)
and :meth:`Task.compute_jacobian` (from the command to the task's velocities), and
overrides :meth:`Task.compute_error` when its values are not vectors (rotations,
poses). :meth:`Task.compute_objective` drives them and must not be overridden: it
steps the interpolator towards the target, adds the interpolator's velocity and the
feedback loop's correction, and returns the Jacobian and the velocity to track. It
keeps what it computed as the task's :class:`TaskSample` of that state, for observers."""

from __future__ import annotations

import copy
from abc import ABC, abstractmethod
from typing import NamedTuple

import numpy as np

from ..exceptions import InvalidParameter
from ..feedback import FeedbackLoop, ProportionalFeedback, make_feedback_loop
from ..interpolators import Interpolator, make_interpolator
from ..parameters import integer_parameter, vector_parameter
from ..spatial import CURRENT, BodyTarget, Current, VectorChart, same_target
from ..state import ControlState


class TaskSample(NamedTuple):
    """A task at one kinematics state (``stamp``), in the task's own terms: ``value``
    (where it is), ``goal`` (the target's value) and ``reference`` (the interpolated
    target of the last cycle, ``None`` before one). ``value`` and ``goal`` are ``None``
    before any state. The objects are shared with the controller: read, never modify."""

    stamp: int
    value: object
    goal: object
    reference: object


class Task(ABC):
    """A motion objective; disabled until enabled.

    Args:
        name: The task's name.
        state: The controller's state (names are resolved against its world).
        dimension: Number of task coordinates.
        target: Initial target; ``None`` holds the current value (position-like tasks)
            or asks for zero velocity (velocity tasks).
        interpolator: An :class:`Interpolator`, a kind, or ``None`` (``"none"``).
        feedback: A :class:`FeedbackLoop` or a kind; default ``proportional(gain=1)``
            for position-like tasks and no correction for velocity tasks.
        weight: Scalar or per-axis weight [-], non-negative.
        priority: Priority level, 0 the highest (used by the strict hierarchy).
        gain: Shortcut setting the feedback loop's proportional gain [1/s], scalar or
            per axis.
        tolerance: When the task counts as :attr:`reached`, one positive number per
            part of :meth:`tolerance_errors` (a scalar is broadcast); default
            :meth:`default_tolerance`.
    """

    kind = "task"
    order = 0
    angular_axes: tuple[int, ...] = ()

    def __init__(self, name: str, state: ControlState, dimension: int, *, target=None,
                 interpolator=None, feedback=None, weight=1.0, priority: int = 0,
                 gain=None, tolerance=None):
        self.name = name
        self.state = state
        self.dimension = dimension
        self._enabled = False
        self._restart = True
        self._held = None
        self._chart = VectorChart()
        self._reference = None
        self._sample: tuple | None = None
        self.tracking_error = np.zeros(dimension)
        """The error from the current value to this cycle's reference, in velocity
        coordinates [task units]; what the feedback loop corrects."""
        self._interpolator: Interpolator
        self._feedback: FeedbackLoop
        self.set_interpolator(interpolator)
        default = ProportionalFeedback(1.0 if self.order == 0 else 0.0)
        self.set_feedback_loop(default if feedback is None else feedback)
        if gain is not None:
            self.gain = gain
        self.weight = weight
        self.priority = priority
        self.tolerance = self.default_tolerance() if tolerance is None else tolerance
        self.target = target

    @abstractmethod
    def compute_value(self, state: ControlState):
        """Hook: the task's current value (vector, rotation matrix or ``pin.SE3``)."""

    def compute_error(self, value, reference) -> np.ndarray:
        """Hook: error from ``value`` to ``reference``, in velocity coordinates; a pure
        function of its arguments. Default ``reference - value``, for vector values."""
        return reference - value

    @abstractmethod
    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        """Hook: dimension x dofs Jacobian from the command to the task velocity."""

    def convert_target(self, value):
        """Hook: a target value checked and converted; default a vector of dimension."""
        return vector_parameter(self.label, "target", value, self.dimension, allow_inf=True)

    def chart_for(self, value):
        """Hook: the chart interpolating from ``value``; default the identity."""
        return self._chart

    def compute_objective(self, state: ControlState) -> tuple[np.ndarray, np.ndarray]:
        """The Jacobian and the velocity the task asks for this cycle."""
        jacobian = self.compute_jacobian(state)
        value = self.compute_value(state)
        if self._restart:
            self._start(state, jacobian, value)
        interpolator = self._interpolator
        goal = self._target if self._constant_goal else self._goal(state)
        if interpolator.passthrough:
            self._reference = goal
            self._sample = (state.kinematics.stamp, value, goal, goal)
            self.tracking_error = self.compute_error(value, goal)
            correction = self._feedback.compute(self.tracking_error)
            return jacobian, goal + correction if self.order else correction
        chart = self._chart
        interpolator.target = chart.to_vector(goal)
        position, rate = interpolator.step()
        reference = chart.from_vector(position)
        feedforward = chart.velocity(position, rate) if self.order == 0 else position
        self._reference = reference
        self._sample = (state.kinematics.stamp, value, goal, reference)
        self.tracking_error = self.compute_error(value, reference)
        return jacobian, feedforward + self._feedback.compute(self.tracking_error)

    def _start(self, state: ControlState, jacobian: np.ndarray, value) -> None:
        """Start from ``value``: the interpolator from it and its current rate (a
        pass-through interpolator has nothing to start)."""
        self._restart = False
        self._held = value.copy() if isinstance(self._target, Current) else None
        self._feedback.reset()
        if self._interpolator.passthrough:
            return
        self._chart = self.chart_for(value)
        if self.order == 0:
            rate = self._chart.rate(jacobian @ state.velocity)
            self._interpolator.restart(self._chart.to_vector(value), rate)
        else:
            self._interpolator.restart(value, np.zeros(self.dimension))

    def _goal(self, state: ControlState, value=None):
        """The target's value this cycle; for ``CURRENT``, the value held since the
        start, or ``value`` (the current one) before any start."""
        target = self._target
        if isinstance(target, Current):
            return value if self._held is None else self._held
        if isinstance(target, BodyTarget):
            return self.value_from_body(state, target)
        return target

    def value_from_body(self, state: ControlState, target: BodyTarget):
        """Hook: value of a tracked body target; tasks that accept one override it."""
        raise InvalidParameter(self.label, "target", target, "no body target for this task")

    @property
    def positional(self) -> bool:
        """Whether the error is a distance to a position-like target [m or rad]: the
        controller's Levenberg-Marquardt damping grows with it."""
        return self.order == 0

    @property
    def label(self) -> str:
        """``kind 'name'``, for messages."""
        return f"{self.kind} '{self.name}'"

    @property
    def target(self):
        """The target: a value, :class:`BodyTarget` or ``CURRENT``.

        Setting it while the task runs (enabled and started) lets the interpolator
        follow the new target from its current reference and velocity (see
        :meth:`Interpolator.retarget`); setting the same target again changes nothing.
        Otherwise, or for ``CURRENT``, the interpolator restarts from the current state.
        """
        return self._target

    @target.setter
    def target(self, value) -> None:
        if value is None:
            value = CURRENT if self.order == 0 else np.zeros(self.dimension)
        if not isinstance(value, (Current, BodyTarget)):
            value = self.convert_target(value)
        running = self._enabled and not self._restart and not isinstance(value, Current)
        if running and same_target(self._target, value):
            return
        self._target = value
        self._constant_goal = not isinstance(value, (Current, BodyTarget))
        self._finite = self._check_finite(value)
        self._sample = None
        if running:
            self._interpolator.retarget()
        else:
            self._restart = True

    @staticmethod
    def _check_finite(target) -> bool:
        if isinstance(target, (Current, BodyTarget)):
            return True
        return bool(np.isfinite(getattr(target, "homogeneous", target)).all())

    def target_is_finite(self) -> bool:
        """Whether the target holds no NaN or infinite number."""
        return self._finite

    @property
    def enabled(self) -> bool:
        """Whether the controller uses the task; enabling restarts its interpolator."""
        return self._enabled

    @enabled.setter
    def enabled(self, value: bool) -> None:
        if value and not self._enabled:
            self._restart = True
        self._enabled = bool(value)
        self.state.revision += 1

    def enable(self) -> None:
        """Enable; the interpolator restarts from the current state at the next cycle."""
        self.enabled = True
        self._restart = True

    def disable(self) -> None:
        """Disable; the controller ignores the task."""
        self.enabled = False

    def reset(self) -> None:
        """Restart the interpolator and feedback loop from the current state."""
        self._restart = True

    def interpolator(self) -> Interpolator:
        """The task's interpolator."""
        return self._interpolator

    def set_interpolator(self, spec, **parameters) -> Interpolator:
        """Replace the interpolator (instance or kind and parameters); restarts."""
        interpolator = make_interpolator(spec, **parameters)
        angular = np.zeros(self.dimension, dtype=bool)
        angular[list(self.angular_axes)] = True
        interpolator.setup(self.dimension, self.state.time_step, angular)
        self._interpolator = interpolator
        self._restart = True
        return interpolator

    def feedback_loop(self) -> FeedbackLoop:
        """The task's feedback loop."""
        return self._feedback

    def set_feedback_loop(self, spec, **parameters) -> FeedbackLoop:
        """Replace the feedback loop (instance or kind and parameters)."""
        feedback = make_feedback_loop(spec, **parameters)
        feedback.setup(self.dimension, self.state.time_step)
        self._feedback = feedback
        return feedback

    @property
    def gain(self):
        """Proportional gain of the feedback loop [1/s]."""
        return self._feedback.gain

    @gain.setter
    def gain(self, value) -> None:
        self._feedback.gain = value

    @property
    def weight(self) -> np.ndarray:
        """Per-axis weight [-] (a scalar is broadcast); read-only, set a new one."""
        return self._weight

    @weight.setter
    def weight(self, value) -> None:
        weight = vector_parameter(self.label, "weight", value, self.dimension, minimum=0.0)
        weight.flags.writeable = False
        self._weight = weight

    @property
    def priority(self) -> int:
        """Priority level, 0 the highest."""
        return self._priority

    @priority.setter
    def priority(self, value: int) -> None:
        self._priority = integer_parameter(self.label, "priority", value)
        self.state.revision += 1

    @property
    def reference_value(self):
        """The interpolated reference of the last cycle (``None`` before one)."""
        return self._reference

    @property
    def tolerance(self) -> np.ndarray:
        """When the task counts as reached: a bound on each part of
        :meth:`tolerance_errors` [task units]."""
        return self._tolerance

    @tolerance.setter
    def tolerance(self, value) -> None:
        self._tolerance = vector_parameter(self.label, "tolerance", value,
                                           len(self.default_tolerance()), minimum=0.0,
                                           strict=True)

    def default_tolerance(self) -> np.ndarray:
        """Hook: the default :attr:`tolerance`; 0.5 deg [rad] per coordinate (per
        second for velocity tasks)."""
        return np.full(self.dimension, np.radians(0.5))

    def tolerance_errors(self) -> np.ndarray:
        """Hook: the parts of the error the :attr:`tolerance` bounds, at the latest
        state; by default each coordinate's magnitude (NaN before any state)."""
        return np.abs(self.error_vector())

    @property
    def interpolated(self) -> bool:
        """Whether the task is enabled and its interpolator has finished."""
        return self._enabled and not self._restart and self._interpolator.finished

    @property
    def reached(self) -> bool:
        """Whether the task is :attr:`interpolated` and every part of its error is within
        its :attr:`tolerance`."""
        return self.interpolated and bool(np.all(self.tolerance_errors() <= self._tolerance))

    def sample(self) -> TaskSample:
        """The task at the latest state: what the controller computed for it, or,
        when the controller has not run on that state, its value and goal now."""
        kinematics = self.state.kinematics
        cached = self._sample
        if kinematics.q is None:
            return TaskSample(kinematics.stamp, None, None, self._reference)
        if cached is not None and cached[0] == kinematics.stamp:
            return TaskSample(*cached)
        value = self.compute_value(self.state)
        return TaskSample(kinematics.stamp, value, self._goal(self.state, value),
                          self._reference)

    def error_vector(self) -> np.ndarray:
        """Error from the current state to the target (NaN before any state)."""
        sample = self.sample()
        if sample.value is None:
            return np.full(self.dimension, np.nan)
        return self.compute_error(sample.value, sample.goal)

    def error_norm(self, value, goal) -> float:
        """What :attr:`error` reports for the task at ``value`` with ``goal``."""
        return float(np.linalg.norm(self.compute_error(value, goal)))

    @property
    def error(self) -> float:
        """Norm of the error to the target, at the latest state [task units]."""
        sample = self.sample()
        if sample.value is None:
            return float("nan")
        return self.error_norm(sample.value, sample.goal)

    @property
    def position_error(self) -> float:
        """Norm of the non-rotation part of the error [m or rad for joints]."""
        error = self.error_vector()
        return float(np.linalg.norm(np.delete(error, list(self.angular_axes))))

    @property
    def orientation_error(self) -> float:
        """Norm of the rotation part of the error [rad]."""
        return float(np.linalg.norm(self.error_vector()[list(self.angular_axes)]))

    def detached(self) -> Task:
        """A copy of the task as it is now that can be pickled, to read its errors in
        another process (:func:`~robocop_dsl.runtime.views.resolve_view`): without its
        interpolator and feedback loop (they may hold solver objects, and no error reads
        them)."""
        twin = copy.copy(self)
        twin._interpolator = twin._feedback = None
        return twin

    def parameters(self) -> dict:
        """The task's parameters by name."""
        return {"target": self._target, "interpolator": self._interpolator,
                "feedback": self._feedback, "weight": self._weight,
                "priority": self._priority, "gain": self.gain,
                "tolerance": self._tolerance}

    def describe(self) -> str:
        """What the task acts on, for ``repr``."""
        return ""

    def __repr__(self) -> str:
        weight = self._weight
        weight = float(weight[0]) if np.all(weight == weight[0]) else weight.tolist()
        target = self._target
        if isinstance(target, np.ndarray):
            target = [round(float(v), 6) for v in target]
        return (f"{type(self).__name__}({self.name!r}, {self.describe()}target={target}, "
                f"interpolator={self._interpolator!r}, feedback={self._feedback!r}, "
                f"weight={weight}, priority={self._priority}, enabled={self.enabled})")
