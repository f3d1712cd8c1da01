"""Parameters of declarations and calls: names, kinds of value, dimensions, ranges."""

from __future__ import annotations

from dataclasses import dataclass

from ..lang import ast
from ..lang.catalogue import (AXES, AXIS_NAMES, BODY, FEEDBACK, FEEDBACKS, INTEGER,
                              INTERPOLATOR, INTERPOLATORS, NORM_OR_AXES, PER_AXIS, PER_DOF,
                              SCALAR, SPACE_AXES, SWITCH, SWITCH_WORDS, TARGET, TOLERANCE,
                              Kind, Parameter, Range, Registry)
from ..lang.units import describe
from .context import CheckContext, Joints
from .targets import check_target
from .tolerance import check_tolerance
from .values import check_per_dof, check_quantity, check_vector, space_dimensions


@dataclass(frozen=True)
class Subject:
    """What a task or constraint drives: its space and, for joints, the joints."""

    kind: Kind
    joints: Joints | None = None

    @property
    def space(self) -> str | None:
        return self.kind.space

    @property
    def dofs(self) -> int | None:
        if self.joints is not None:
            return self.joints.dofs
        return None if self.kind.subject == "joint_group" else 1

    @property
    def axes(self) -> int | None:
        """The task's coordinates: one per dof for joints, else its space's axes."""
        if self.kind.subject == "joint_group":
            return self.dofs
        return SPACE_AXES.get(self.space)


def check_value(ctx: CheckContext, parameter: Parameter, value: ast.Value, subject: Subject,
                what: str) -> tuple[float, ...] | None:
    """Check one value given to ``parameter`` (of a declaration, a call or an action);
    return its numbers in SI (one per dof for ``PER_DOF``) when it has usable ones."""
    if ctx.opaque(value):
        return None
    dimensions = space_dimensions(parameter.dimension, subject.space, subject.joints)
    numbers = None
    if parameter.kind == SCALAR:
        if not isinstance(value, ast.Quantity):
            ctx.error("wrong-value", f"{what} expects {describe(dimensions)}", value.span)
            return None
        number = check_quantity(ctx, value, dimensions, what)
        numbers = None if number is None else (number,)
    elif parameter.kind == PER_DOF:
        numbers = check_per_dof(ctx, value, dimensions, what, subject.dofs)
    elif parameter.kind == PER_AXIS:
        numbers = check_per_dof(ctx, value, dimensions, what, subject.axes)
    elif parameter.kind == NORM_OR_AXES:
        numbers = _check_norm_or_axes(ctx, value, dimensions, what)
    elif parameter.kind == TOLERANCE:
        check_tolerance(ctx, value, subject.space, subject.joints, what)
        return None
    elif parameter.kind == SWITCH:
        _check_switch(ctx, value, what)
    elif parameter.kind == INTEGER:
        if (not isinstance(value, ast.Quantity) or value.unit is not None
                or not value.value.is_integer()):
            bound = f", {parameter.valid.text}" if parameter.valid else ""
            ctx.error("wrong-value", f"{what} expects a whole number{bound}", value.span)
            return None
        numbers = (value.value,)
    elif parameter.kind == BODY:
        check_body_value(ctx, value, what)
    elif parameter.kind == AXES:
        _check_axes(ctx, value, what)
    elif parameter.kind == INTERPOLATOR:
        check_call(ctx, value, INTERPOLATORS, "unknown-interpolator", subject, what)
    elif parameter.kind == FEEDBACK:
        check_call(ctx, value, FEEDBACKS, "unknown-feedback", subject, what)
    elif parameter.kind == TARGET:
        check_target(ctx, value, subject.kind, subject.joints, what)
    if numbers is not None and parameter.valid is not None:
        check_range(ctx, parameter.valid, numbers, value, subject.joints, what)
    return numbers


def _check_norm_or_axes(ctx: CheckContext, value: ast.Value, dimensions: tuple[str, ...],
                        what: str) -> tuple[float, ...] | None:
    """One number (a bound on the norm) or a 3-vector (one bound per axis), in SI."""
    if isinstance(value, ast.Quantity):
        number = check_quantity(ctx, value, dimensions, what)
        return None if number is None else (number,)
    if isinstance(value, ast.Vector):
        return check_vector(ctx, value, dimensions, what, 3)
    ctx.error("wrong-value", f"{what} expects {describe(dimensions)}", value.span,
              "one number bounds the norm, a vector [x, y, z] bounds each axis")
    return None


def _check_axes(ctx: CheckContext, value: ast.Value, what: str) -> None:
    """A list of the world's axes, each once: ``[x, z]``."""
    hint = "for example [z] or [x, y]: the world's axes are " + ", ".join(AXIS_NAMES)
    names = value.values if isinstance(value, ast.Vector) and value.unit is None else ()
    if not names or not all(isinstance(n, ast.NameElement) and not n.negative
                            for n in names):
        ctx.error("wrong-value", f"{what} expects a list of the world's axes", value.span,
                  hint)
        return
    seen = set()
    for element in names:
        name = element.name
        if name.text not in AXIS_NAMES:
            lower = name.text.lower()
            ctx.unknown("unknown-axis", "axis", name, AXIS_NAMES,
                        f"did you mean '{lower}'?" if lower in AXIS_NAMES else hint)
        elif name.text in seen:
            ctx.error("wrong-value", f"{what} lists axis '{name.text}' twice", name.span,
                      "list each axis once")
        seen.add(name.text)


def _check_switch(ctx: CheckContext, value: ast.Value, what: str) -> None:
    if not (isinstance(value, ast.Reference) and value.name.text in SWITCH_WORDS):
        ctx.error("wrong-value", f"{what} expects true or false", value.span,
                  "for example: enabled = true")


def check_range(ctx: CheckContext, valid: Range, numbers: tuple[float, ...],
                value: ast.Value, joints: Joints | None, what: str) -> None:
    """Report numbers [SI] outside ``valid``: a scalar once, each bad element of a vector."""
    if not isinstance(value, ast.Vector):
        fault = valid.fault(numbers[0])
        if fault:
            ctx.error("wrong-value", f"{what} {fault}", value.span, f"valid values: {valid.text}")
        return
    unit = f" {value.unit.text}" if value.unit else ""
    for index, (number, written) in enumerate(zip(numbers, value.values)):
        fault = valid.fault(number)
        if fault:
            where = f"joint {index + 1} of '{joints.name}'; " if joints else ""
            ctx.error("wrong-value", f"{what}: value {index + 1} ({written:g}{unit}) {fault}",
                      value.span, f"{where}valid values: {valid.text}")


def check_body_value(ctx: CheckContext, value: ast.Value, what: str) -> None:
    if not isinstance(value, ast.Reference):
        ctx.error("wrong-value", f"{what} expects a body name", value.span,
                  "for example 'world' or a body of the world")
        return
    check_body(ctx, value.name)


def check_body(ctx: CheckContext, name: ast.Name) -> bool:
    """Report a body the world does not have; ``True`` when it exists (or no world)."""
    if ctx.world.has_body(name.text) or name.text in ctx.generic:
        return True
    ctx.unknown("unknown-body", "body", name, ctx.world.body_names())
    return False


def check_parameters(ctx: CheckContext, given: list[tuple[ast.Name | None, ast.Value]],
                     kind: Kind, subject: Subject, owner: str, span
                     ) -> dict[str, tuple[ast.Value, tuple[float, ...] | None]]:
    """Check a declaration's ``name = value`` list or a call's arguments against ``kind``;
    return each parameter's value and its numbers in SI (``None`` when unusable).

    Positional arguments (name ``None``) take the parameters in their declared order.
    """
    seen: dict[str, ast.Name | None] = {}
    numbers: dict[str, tuple[ast.Value, tuple[float, ...] | None]] = {}
    for index, (name, value) in enumerate(given):
        if name is None:
            if index >= len(kind.parameters):
                ctx.error("wrong-arguments",
                          f"{owner} takes at most {len(kind.parameters)} arguments",
                          value.span)
                continue
            parameter = kind.parameters[index]
        else:
            parameter = kind.parameter(name.text)
            if parameter is None:
                ctx.unknown("unknown-parameter", "parameter", name, kind.parameter_names,
                            _parameters_hint(kind), where=f" for {owner}")
                continue
        if parameter.name in seen:
            ctx.error("duplicate-name", f"parameter '{parameter.name}' is given twice",
                      (name or value).span)
            continue
        if not _applies(parameter, subject):
            ctx.error("unknown-parameter", f"{owner} takes no '{parameter.name}' for a "
                      f"{subject.kind.name} task", (name or value).span,
                      f"'{parameter.name}' applies to {_spaces_text(parameter)} tasks")
            continue
        seen[parameter.name] = name
        checked = check_value(ctx, parameter, value, subject, f"'{parameter.name}'")
        numbers[parameter.name] = (value, checked)
    for low, high in kind.ordered:
        check_order(ctx, low, high, numbers, subject.joints)
    for name, bound in kind.bounded:
        _check_bounded(ctx, name, bound, numbers)
    missing = [p.name for p in kind.parameters if p.required and p.name not in seen]
    if missing:
        ctx.error("missing-parameter",
                  f"{owner} needs {', '.join(repr(m) for m in missing)}", span,
                  _parameters_hint(kind))
    return numbers


def check_order(ctx: CheckContext, low: str, high: str,
                numbers: dict[str, tuple[ast.Value, tuple[float, ...] | None]],
                joints: Joints | None, located: str | None = None,
                declared: str | None = None) -> None:
    """Report the first joint where ``low`` is above ``high`` [SI]; an absent one is
    the URDF limit, neither given is left to the world's checks, an unusable one to its
    own error. The error is at the value of ``located`` (default: the first given);
    ``declared`` names one that the constraint's declaration gives (for an action)."""
    given = [name for name in (low, high) if name in numbers]
    if joints is None or not given or any(numbers[n][1] is None for n in given):
        return
    lows = numbers[low][1] if low in numbers else joints.lower
    highs = numbers[high][1] if high in numbers else joints.upper
    bad = [i for i, (a, b) in enumerate(zip(lows, highs)) if a > b]
    if not bad:
        _check_against_urdf(ctx, low, high, numbers, joints, located, given)
        return
    index = bad[0]
    unit = "m" if joints.joint_types[index] == "prismatic" else "rad"
    more = f" (and {len(bad) - 1} more joints)" if len(bad) > 1 else ""
    span = numbers[located or given[0]][0].span
    defaulted = "" if len(given) == 2 else (
        f", the URDF's {'upper' if low in numbers else 'lower'} limit that '"
        f"{high if low in numbers else low}' defaults to")
    if declared is not None:
        defaulted = f", '{declared}' as declared at {ctx.where(numbers[declared][0].span)}"
    ctx.error("inverted-limits",
              f"'{low}' is above '{high}' at joint {index + 1} of '{joints.name}': "
              f"{lows[index]:.4g} > {highs[index]:.4g} {unit}{defaulted}{more}", span,
              f"every value of '{low}' must be at most the matching value of '{high}'")


def _check_bounded(ctx: CheckContext, name: str, bound: str, numbers: dict) -> None:
    """Report the first value of ``name`` whose magnitude is above the matching one of
    ``bound`` (a single number stands for every dof) [SI]."""
    values, limits = (numbers.get(n, (None, None))[1] for n in (name, bound))
    if not values or not limits:
        return
    count = max(len(values), len(limits))
    pairs = zip(values * count if len(values) == 1 else values,
                limits * count if len(limits) == 1 else limits)
    bad = next((i for i, (value, limit) in enumerate(pairs) if abs(value) > limit), None)
    if bad is None:
        return
    ctx.error("wrong-value", f"'{name}' is above '{bound}'" + (
        f" at dof {bad + 1}" if count > 1 else ""), numbers[name][0].span,
              f"no trajectory reaches a velocity above '{bound}': the reference would "
              "hold where it is")


def _check_against_urdf(ctx: CheckContext, low: str, high: str, numbers, joints: Joints,
                        located: str | None, given: list[str]) -> None:
    """Report the first joint that ``low`` puts above its URDF upper limit, or ``high``
    below its lower one: the two ranges leave it no position."""
    for name, values, urdf, sign, side in (
            (low, numbers[low][1] if low in numbers else None, joints.upper, 1, "upper"),
            (high, numbers[high][1] if high in numbers else None, joints.lower, -1, "lower")):
        if values is None:
            continue
        bad = [i for i, (a, b) in enumerate(zip(values, urdf)) if sign * (a - b) > 0]
        if not bad:
            continue
        index = bad[0]
        unit = "m" if joints.joint_types[index] == "prismatic" else "rad"
        more = f" (and {len(bad) - 1} more joints)" if len(bad) > 1 else ""
        ctx.error("inverted-limits",
                  f"'{name}' is {'above' if sign > 0 else 'below'} the URDF's {side} limit "
                  f"at joint {index + 1} of '{joints.name}': {values[index]:.4g} "
                  f"{'>' if sign > 0 else '<'} {urdf[index]:.4g} {unit}{more}",
                  numbers[located if located in numbers else name][0].span,
                  "the joint keeps within both ranges: they must overlap")
        return


def _applies(parameter: Parameter, subject: Subject) -> bool:
    """Whether ``parameter`` applies to the space of ``subject`` (unknown: yes)."""
    return parameter.spaces is None or subject.space is None \
        or subject.space in parameter.spaces


def _spaces_text(parameter: Parameter) -> str:
    spaces = [s.replace("_", " ") for s in parameter.spaces]
    return ", ".join(spaces[:-1]) + (" or " if len(spaces) > 1 else "") + spaces[-1]


def _parameters_hint(kind: Kind) -> str:
    if not kind.parameters:
        return f"{kind.name} takes no parameters"
    return f"{kind.name} takes " + ", ".join(p.name for p in kind.parameters)


def check_call(ctx: CheckContext, value: ast.Value, registry: Registry, code: str,
               subject: Subject, what: str) -> None:
    """An interpolator or feedback law: ``kind(args)`` or a bare ``kind``."""
    if isinstance(value, ast.Reference):
        kind_name, arguments, span = value.name, (), value.span
    elif isinstance(value, ast.Call):
        kind_name, arguments, span = value.kind, value.arguments, value.span
    else:
        ctx.error("wrong-value", f"{what} expects {registry.family} such as "
                  f"{', '.join(registry.names()[:3])}", value.span)
        return
    kind = registry.get(kind_name.text)
    if kind is None:
        ctx.unknown(code, registry.family, kind_name, registry.names(),
                    f"{registry.family}s: {', '.join(registry.names())}")
        return
    given = [(a.name, a.value) for a in arguments]
    check_parameters(ctx, given, kind, subject, f"{kind.name}()", span)
