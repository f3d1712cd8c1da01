"""Run-time values compiled: each ``var`` by its qualified name, expressions as trees of
specs in SI, the actions that assign vars and the ``log`` texts that print them.

A var the mission declares keeps its name; one a behaviour declares gets the path of
the machine of each instance (``approach/tries``): one var per instance.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..check.values import to_si
from ..check.variables import KINDS, PLACEHOLDER, symbol
from ..diagnostics import Span
from ..lang import ast


@dataclass(frozen=True)
class VarSpec:
    """A var: its qualified name, kind, size (1, or 3 for a ``position``), SI unit and
    first value (``None``: none until assigned)."""

    name: str
    kind: str
    size: int
    unit: str
    initial: object = None


@dataclass(frozen=True)
class Constant:
    value: float | tuple


@dataclass(frozen=True)
class VarValue:
    """The current value of a var (qualified name)."""

    name: str


@dataclass(frozen=True)
class Arithmetic:
    operator: str
    left: object
    right: object


@dataclass(frozen=True)
class Negated:
    operand: object


@dataclass(frozen=True)
class PositionMeasure:
    """A body's world position [m]: the 3-vector, or the component ``axis`` (0..2)."""

    body: str
    axis: int | None = None


@dataclass(frozen=True)
class WrenchMeasure:
    """What a body exerts on the environment, from its force sensor: the force [N] or
    the torque [N m], its norm or the world component ``axis`` (0..2)."""

    body: str
    torque: bool
    axis: int | None = None


@dataclass(frozen=True)
class ContactCondition:
    """True while the physics has a contact between two bodies or sets."""

    first: str
    second: str


@dataclass(frozen=True)
class SetVarAction:
    name: str
    value: object
    span: Span = field(compare=False)


@dataclass(frozen=True)
class LogField:
    """A ``{NAME}`` of a log text: the var it prints and its SI unit."""

    placeholder: str
    var: str
    unit: str


class VarScope:
    """The vars a machine sees: its own, then those of the machines around it (for a
    behaviour instance, the mission's own only), by local name."""

    def __init__(self, names: dict[str, str] | None = None):
        self.names = dict(names or {})

    def inner(self, machine: ast.Machine, path: str, lexical: "VarScope") -> "VarScope":
        """The scope of ``machine`` at ``path``: ``lexical`` and its own vars."""
        names = dict(lexical.names)
        names.update({v.name.text: qualified(path, v.name.text) for v in machine.variables})
        return VarScope(names)

    def __getitem__(self, name: str) -> str:
        return self.names[name]


def qualified(path: str, name: str) -> str:
    return f"{path}/{name}" if path else name


def var_specs(machine: ast.Machine, path: str, scope: VarScope, measure) -> list[VarSpec]:
    """The vars ``machine`` declares, qualified by ``path``."""
    found = []
    for decl in machine.variables:
        _, size = KINDS[decl.kind.text]
        initial = (expression(decl.value, scope, measure) if decl.value is not None
                   else None)
        found.append(VarSpec(qualified(path, decl.name.text), decl.kind.text, size,
                             symbol(KINDS[decl.kind.text][0]), initial))
    return found


def expression(node, scope: VarScope, measure):
    """The spec of a checked expression; ``measure(node)`` compiles the measures that
    read tasks and states."""
    if isinstance(node, ast.Quantity):
        return Constant(to_si(node))
    if isinstance(node, ast.Vector):
        from ..check.values import vector_to_si

        return Constant(vector_to_si(node))
    if isinstance(node, ast.Binary):
        return Arithmetic(node.operator, expression(node.left, scope, measure),
                          expression(node.right, scope, measure))
    if isinstance(node, ast.Negative):
        return Negated(expression(node.operand, scope, measure))
    if isinstance(node, (ast.Variable, ast.Reference)):
        return VarValue(scope[node.name.text])
    if isinstance(node, ast.Wrench):
        return wrench(node)
    position = body_position(node)
    return position if position is not None else measure(node)


def wrench(node: ast.Wrench) -> WrenchMeasure:
    axis = "xyz".index(node.axis.text) if node.axis is not None else None
    return WrenchMeasure(node.body.text, node.torque, axis)


def body_position(node) -> PositionMeasure | None:
    """``BODY.position[.axis]`` (checked: a member whose field or region is position
    and whose owner is a body), else ``None``."""
    if not isinstance(node, ast.Member):
        return None
    if node.region is not None and node.region.text == "position":
        return PositionMeasure(node.owner.text, "xyz".index(node.field.text))
    if node.region is None and node.field.text == "position":
        return PositionMeasure(node.owner.text)
    return None


def log_fields(text: str, scope: VarScope, units: dict[str, str]) -> tuple[LogField, ...]:
    """The ``{NAME}`` of a log text (constants were written in by the checker)."""
    found = []
    for match in PLACEHOLDER.finditer(text):
        name = scope[match.group(1).strip()]
        found.append(LogField(match.group(0), name, units[name]))
    return tuple(found)
