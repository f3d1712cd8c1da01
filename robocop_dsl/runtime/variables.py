"""The run's vars: their values, the closures that compute expressions, and what reads
them (a target with a var, a log text).

Values are SI: a float, or a 3-vector (``numpy`` array) for a ``position``. A var
without a first value holds NaN until assigned (``check`` warns when it can be read
before).
"""

from __future__ import annotations

import math
import operator

import numpy as np

from ..compile import spec as s
from ..compile import variables as v
from ..diagnostics import RobocopError


def _divided(numerator, divisor):
    """``numerator / divisor``; a zero divisor is a fault that says so (a condition may
    divide every cycle: a number is compared as it is, no array made of it)."""
    if not divisor.all() if isinstance(divisor, np.ndarray) else divisor == 0:
        raise RobocopError("division by zero: the divisor of a '/' is 0")
    return numerator / divisor


_ARITHMETIC = {"+": operator.add, "-": operator.sub, "*": operator.mul, "/": _divided}


class Variables:
    """The vars of a run by qualified name: ``specs`` and current ``values``."""

    def __init__(self, specs):
        self.specs = {spec.name: spec for spec in specs}
        self.values: dict = {}
        self._initial = {spec.name: evaluator(spec.initial) for spec in specs
                         if spec.initial is not None}

    def __bool__(self) -> bool:
        return bool(self.specs)

    def start(self, runner) -> None:
        """Give every var its first value (read at the first cycle's state)."""
        for name, spec in self.specs.items():
            first = self._initial.get(name)
            self.values[name] = (_stored(first(runner, None), spec) if first is not None
                                 else _nothing(spec))

    def set(self, name: str, value):
        """Store ``value`` [SI] in var ``name``; the stored value."""
        stored = _stored(value, self.specs[name])
        self.values[name] = stored
        return stored

    def text(self, name: str) -> str:
        """A var's value as a log prints it: ``3``, ``0.7512 m``, ``[0.5, 0, 0.77] m``."""
        spec, value = self.specs[name], self.values[name]
        unit = f" {spec.unit}" if spec.unit else ""
        if spec.size == 3:
            return "[" + ", ".join(f"{x:.6g}" for x in value) + "]" + unit
        if spec.kind == "count" and math.isfinite(value):
            return str(int(value))
        return f"{value:.6g}{unit}"


def _stored(value, spec):
    if spec.size == 3:
        return np.array(value, dtype=float).reshape(3)
    value = float(value)
    return float(round(value)) if spec.kind == "count" and math.isfinite(value) else value


def _nothing(spec):
    return np.full(3, np.nan) if spec.size == 3 else math.nan


def evaluator(node, remote=None):
    """A function ``value(runner, owner)`` [SI] of an expression spec; ``owner`` is the
    activation of the state owning the clause (``None`` in an action); ``remote``: in a
    cascade, how tasks of the other controllers are read (see :mod:`.build`)."""
    if isinstance(node, v.Constant):
        value = np.array(node.value) if isinstance(node.value, tuple) else node.value
        return lambda runner, owner: value
    if isinstance(node, v.VarValue):
        return lambda runner, owner, name=node.name: runner.variables.values[name]
    if isinstance(node, v.Arithmetic):
        left, right = evaluator(node.left, remote), evaluator(node.right, remote)
        apply = _ARITHMETIC[node.operator]
        return lambda runner, owner: apply(left(runner, owner), right(runner, owner))
    if isinstance(node, v.Negated):
        operand = evaluator(node.operand, remote)
        return lambda runner, owner: -operand(runner, owner)
    if isinstance(node, v.PositionMeasure):
        return _position(node)
    if isinstance(node, v.WrenchMeasure):
        return _wrench(node)
    from .build import measure

    return measure(node, remote)


def _position(node: v.PositionMeasure):
    def position(runner, owner, body=node.body, axis=node.axis):
        translation = runner.kinematics.body_pose(body).translation
        return translation.copy() if axis is None else float(translation[axis])
    return position


def _wrench(node: v.WrenchMeasure):
    part = slice(3, 6) if node.torque else slice(0, 3)

    def wrench(runner, owner, body=node.body, axis=node.axis):
        value = runner.wrench(body)[part]
        return float(np.linalg.norm(value)) if axis is None else float(value[axis])
    return wrench


def resolved(target, runner):
    """A target spec with the vars of its vectors replaced by their values."""
    def values(vector):
        if vector is None or all(isinstance(x, float) for x in vector):
            return vector
        return tuple(float(evaluator(x)(runner, None)) if not isinstance(x, float) else x
                     for x in vector)

    if isinstance(target, s.BodyTarget):
        return s.BodyTarget(target.body, values(target.offset))
    if isinstance(target, s.PoseTarget):
        return s.PoseTarget(values(target.position), values(target.rpy))
    if isinstance(target, s.VectorTarget):
        return s.VectorTarget(values(target.values))
    return target


def log_text(action: s.LogAction, runner) -> str:
    """A log text with each ``{NAME}`` replaced by the var's value and unit."""
    text = action.text
    for field in action.fields:
        text = text.replace(field.placeholder, runner.variables.text(field.var))
    return text
