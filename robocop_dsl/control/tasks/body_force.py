"""The ``body_force`` task: make a body press on its environment with a given force,
by velocity-resolved force control (admittance), as RoboCoP does in a kinematic
controller."""

from __future__ import annotations

import numpy as np

from ...diagnostics import RobocopError
from ..exceptions import ControlError, InvalidParameter
from ..feedback import FeedbackLoop
from ..parameters import vector_parameter
from ..state import ControlState
from .base import Task, TaskSample

AXIS_NAMES = ("x", "y", "z")


class Admittance(FeedbackLoop):
    """``velocity = clip(gain * error, -max_velocity, max_velocity)``, axis by axis: a
    force error [N] to a reference velocity [m/s].

    Args:
        gain: Admittance [(m/s)/N], scalar or per axis, non-negative.
        max_velocity: Bound on each axis' velocity [m/s], scalar or per axis, positive.
    """

    kind = "admittance"

    def __init__(self, gain, max_velocity):
        super().__init__()
        self._gain = vector_parameter(self.kind, "gain", gain, np.size(gain), minimum=0.0)
        self._max = vector_parameter(self.kind, "max_velocity", max_velocity,
                                     np.size(max_velocity), minimum=0.0, strict=True)

    def validate(self) -> None:
        """Size the gain and the bound for the task's axes (one number broadcast)."""
        one = (lambda values: values[0] if values.size == 1 else values)
        self.gain, self.max_velocity = one(self._gain), one(self._max)

    def compute(self, error: np.ndarray) -> np.ndarray:
        return np.clip(self._gain * error, -self._max, self._max)

    @property
    def gain(self) -> np.ndarray:
        """Admittance per axis [(m/s)/N]."""
        return self._gain

    @gain.setter
    def gain(self, value) -> None:
        self._gain = vector_parameter(self.kind, "gain", value, self.dimension, minimum=0.0)

    @property
    def max_velocity(self) -> np.ndarray:
        """Bound on each axis' reference velocity [m/s]."""
        return self._max

    @max_velocity.setter
    def max_velocity(self, value) -> None:
        self._max = vector_parameter(self.kind, "max_velocity", value, self.dimension,
                                     minimum=0.0, strict=True)

    def parameters(self) -> dict:
        return {"gain": self._gain, "max_velocity": self._max}


class BodyForceTask(Task):
    """The force [N] ``body`` exerts on its environment, along some axes of the world.

    The measured force is the body's force sensor (``state.sensors``): what the body and
    everything it carries exert on the environment, in the world frame, so that pressing
    down on a table is a negative ``z``; the target follows the same convention. Each
    cycle the reference velocity of the body's origin along each controlled axis is
    ``clip(gain * (target - measured), -max_velocity, max_velocity)`` [m/s]; the task's
    rows are the linear rows of the body's Jacobian for those axes (world frame), so
    that it shares the QP with the other tasks under every constraint. The other axes
    are left free. The error is the force error on the controlled axes [N].

    Args:
        name: The task's name.
        state: The controller's state.
        body: The pressing body; it needs a force sensor.
        gain: Admittance [(m/s)/N], one number or one per controlled axis, >= 0.
        max_velocity: Bound on each axis' reference velocity [m/s], > 0.
        target: The force to exert [N], a 3-vector in the world frame; ``None``: zero
            (the body yields to whatever pushes it); ``CURRENT``: the force measured
            when the task starts.
        axes: The controlled world axes: indices (0, 1, 2) or names (``"x"``, ``"y"``,
            ``"z"``); default all three.
        tolerance: The task is reached when every controlled axis' force error is
            within it [N]; default 1 N.
        weight: Scalar or per-axis weight [-].
        priority: Priority level, 0 the highest.
    """

    kind = "body_force"
    positional = False

    def __init__(self, name: str, state: ControlState, body: str, *, gain, max_velocity,
                 target=None, axes=(0, 1, 2), tolerance=None, weight=1.0, priority: int = 0):
        self.body = body
        self.body_id = state.body(body)
        self.axes = _axes(f"{self.kind} '{name}'", axes)
        super().__init__(name, state, len(self.axes), target=target,
                         feedback=Admittance(gain, max_velocity), weight=weight,
                         priority=priority, tolerance=tolerance)

    @property
    def target(self):
        """The force to exert [N] (world frame), or ``CURRENT``."""
        return self._target

    @target.setter
    def target(self, value) -> None:
        Task.target.fset(self, np.zeros(3) if value is None else value)

    @property
    def max_velocity(self) -> np.ndarray:
        """Bound on each controlled axis' reference velocity [m/s]."""
        return self._feedback.max_velocity

    @max_velocity.setter
    def max_velocity(self, value) -> None:
        self._feedback.max_velocity = value

    def convert_target(self, value) -> np.ndarray:
        return vector_parameter(self.label, "target", value, 3)

    def compute_value(self, state: ControlState) -> np.ndarray:
        """The measured force [N], world frame."""
        if state.sensors is None:
            raise ControlError(f"{self.label} reads the force of '{self.body}', and the "
                               "controller has no force sensors (Controller.sensors)")
        return np.asarray(state.sensors.wrench(self.body), dtype=float)[:3]

    def compute_error(self, value, reference) -> np.ndarray:
        return (reference - value)[self.axes]

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return state.jacobian(self.body_id)[self.axes]

    def sample(self) -> TaskSample:
        """:meth:`Task.sample`; no value while the body's force has no reading (the
        cycle's computation said why)."""
        try:
            return super().sample()
        except RobocopError:
            return TaskSample(self.state.kinematics.stamp, None, None, self._reference)

    def default_tolerance(self) -> np.ndarray:
        """1 N."""
        return np.ones(1)

    def tolerance_errors(self) -> np.ndarray:
        """The largest force error of the controlled axes [N]."""
        return np.array([np.max(np.abs(self.error_vector()))])

    def describe(self) -> str:
        return f"body={self.body!r}, axes={''.join(AXIS_NAMES[a] for a in self.axes)!r}, "

    def parameters(self) -> dict:
        return {"body": self.body, "axes": self.axes, "max_velocity": self.max_velocity,
                **super().parameters()}


def _axes(owner: str, axes) -> np.ndarray:
    """World axes given as indices or names, as an index array without repeats."""
    try:
        indices = [AXIS_NAMES.index(a) if isinstance(a, str) else int(a) for a in axes]
    except (TypeError, ValueError):
        indices = None
    if (not indices or len(set(indices)) != len(indices)
            or not all(0 <= i < 3 for i in indices)):
        raise InvalidParameter(owner, "axes", axes,
                               "one or more of the world's axes, each once: 0, 1, 2 or "
                               "'x', 'y', 'z'")
    return np.array(indices, dtype=int)
