"""Hover: a type's documentation and parameters, a body's parent and world placement,
a joint group's joints and limits, a constant's value, a var's kind, first value and
scope, a declaration's header."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from lsprotocol import types

from ..lang import ast
from ..lang.catalogue import CONSTRAINTS, FEEDBACKS, INTERPOLATORS, TASKS, Kind
from ..lang.formatter import format_value, item_lines
from ..lang.units import UNITS
from . import names
from .completion import units_text
from .navigation import target_at
from .positions import to_range
from .project import Project
from .resolve import BODY, JOINT, JOINT_GROUP


def _kind_text(kind: Kind, family: str) -> str:
    lines = [f"**{kind.name}** ({family}): {kind.doc}", ""]
    for parameter in kind.parameters:
        need = "required" if parameter.required else (
            f"default {parameter.default}" if parameter.default is not None else "optional")
        doc = f": {parameter.doc}" if parameter.doc else ""
        lines.append(f"- `{parameter.name}` ({units_text(parameter, family)}; {need}){doc}")
    return "\n".join(lines)


def _numbers(values, digits: int = 3) -> str:
    return "[" + ", ".join("inf" if math.isinf(v) and v > 0 else "-inf" if math.isinf(v)
                           else f"{v:.{digits}g}" for v in values) + "]"


def _body_text(world, name: str) -> str:
    info = world.body(name)
    pose = world.body_pose(name, world.initial_configuration())
    rpy = _rpy(pose.rotation)
    lines = [f"**{name}** (body)", "",
             f"- parent: `{info.parent}` through joint `{info.joint}`" if info.parent
             else "- the world's root",
             f"- world position at the initial configuration: {_numbers(pose.translation)} m",
             f"- world orientation (roll, pitch, yaw): {_numbers(rpy)} rad",
             f"- defined at {info.where}"]
    return "\n".join(lines)


def _rpy(rotation: np.ndarray) -> list[float]:
    import pinocchio as pin

    return list(pin.rpy.matrixToRpy(rotation))


def _group_text(world, name: str, kind: str) -> str:
    group = world.joint_group(name)
    lines = [f"**{name}** ({kind}, {group.dofs} dofs)", "",
             "| joint | lower | upper | max velocity |", "|---|---|---|---|"]
    for joint_name in group.joints:
        joint = world.joint(joint_name)
        lines.append(f"| {joint_name} | {_numbers(joint.lower)} | {_numbers(joint.upper)} "
                     f"| {_numbers(joint.max_velocity)} |")
    return "\n".join(lines)


def _kind_of_var(kind: str) -> str | None:
    """What a var of ``kind`` holds."""
    from ..check.variables import KINDS, describe

    if kind == "count":
        return "a count: a whole number"
    known = KINDS.get(kind)
    return describe(*known) if known else None


def _scope_text(declared: names.Occurrence) -> str:
    """Where a var is declared and who sees it."""
    region = f"region `{declared.context}`" if declared.context else None
    if declared.behavior is not None:
        inside = f"{region} of " if region else ""
        return (f"declared in {inside}behavior `{declared.behavior.name.text}`: one per "
                "instance")
    if region is not None:
        return f"declared in {region}: seen there and in the machines inside it"
    return "declared at the top of the file: seen everywhere, behaviours included"


def _var_text(parsed, node: ast.VarDecl) -> str:
    text = f"```mission\n{item_lines(node)[0].text}\n```"
    kind = _kind_of_var(node.kind.text)
    declared = next((o for o in parsed.occurrences if o.declares and o.node is node), None)
    details = [kind] if kind else []
    details += [_scope_text(declared)] if declared is not None else []
    return text + "".join(f"\n\n{line}" for line in details)


def _declaration_text(node) -> str:
    header = item_lines(node)[0].text.rstrip(" {")
    text = f"```mission\n{header}\n```"
    if isinstance(node, (ast.TaskDecl, ast.ConstraintDecl)):
        registry = TASKS if isinstance(node, ast.TaskDecl) else CONSTRAINTS
        kind = registry.get(node.kind.text)
        text += f"\n\n{kind.doc}" if kind else ""
    if isinstance(node, ast.Let):
        text = f"```mission\nlet {node.name.text} = {format_value(node.value)}\n```"
    if isinstance(node, ast.BehaviorDecl):
        outcomes = [s.name.text for s in node.machine.states if s.final]
        text += f"\n\noutcomes: {', '.join(outcomes) or 'none'}"
    return text


def _catalogue_text(occurrence: names.Occurrence) -> str | None:
    """The text for a name of the language's vocabulary: a type, a parameter, a unit."""
    text = occurrence.text
    if occurrence.role == names.TYPE:
        registry = TASKS if occurrence.context == names.TASK else CONSTRAINTS
        kind = registry.get(text)
        return _kind_text(kind, registry.family) if kind else None
    if occurrence.role == names.CALL:
        for registry in (INTERPOLATORS, FEEDBACKS):
            if registry.get(text) is not None:
                return _kind_text(registry.get(text), registry.family)
    if occurrence.role == names.SETTING:
        family, _, kind_name = occurrence.context.partition(":")
        kind = (TASKS if family == names.TASK else CONSTRAINTS).get(kind_name)
        parameter = kind.parameter(text) if kind else None
        if parameter is not None:
            return (f"**{text}** ({units_text(parameter, family)})"
                    + (f": {parameter.doc}" if parameter.doc else ""))
    if occurrence.role == names.ARGUMENT:
        for registry in (INTERPOLATORS, FEEDBACKS):
            kind = registry.get(occurrence.context or "")
            parameter = kind.parameter(text) if kind else None
            if parameter is not None:
                return (f"**{text}** ({units_text(parameter, 'task')})"
                        + (f": {parameter.doc}" if parameter.doc else ""))
    if occurrence.role == names.KIND and occurrence.context == names.VAR:
        kind = _kind_of_var(text)
        return f"**{text}** (var kind): {kind}" if kind else None
    if occurrence.role == names.UNIT and text in UNITS:
        unit = UNITS[text]
        return f"**{text}**: {unit.dimension}, {unit.to_si:g} in SI"
    return None


def hover(project: Project, path: Path, line: int, column: int) -> types.Hover | None:
    """The hover text for the name at a 1-based position."""
    parsed, occurrence, target = target_at(project, path, line, column)
    if occurrence is None:
        return None
    text = _catalogue_text(occurrence)
    if text is None and target is not None:
        world = project.world(path)
        if target.kind == BODY and world is not None:
            text = _body_text(world, target.name)
        elif target.kind in (JOINT_GROUP, JOINT) and world is not None:
            text = _group_text(world, target.name, target.kind)
        elif isinstance(target.node, ast.VarDecl):
            text = _var_text(parsed, target.node)
        elif target.node is not None and not isinstance(target.node, ast.Region):
            text = _declaration_text(target.node)
        else:
            text = f"**{target.name}** ({target.kind})"
        text += f"\n\n{target.path.name}:{target.span.line}"
    if text is None:
        return None
    return types.Hover(types.MarkupContent(types.MarkupKind.Markdown, text),
                       range=to_range(occurrence.name.span))
