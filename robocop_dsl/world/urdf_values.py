"""The numbers and types of a URDF's joints and links, checked before anything reads
them: a joint type URDF has, a ``<limit>`` on every revolute and prismatic joint with
the ``velocity`` and ``effort`` every limit needs, limits that are finite numbers in SI
(no units, no NaN), velocity and effort limits not negative, a lower limit not above
the upper one, a moving joint's axis not zero, origins, axes and inertias of numbers,
and names that are unique. Each problem is located at the attribute: what URDF parsers
(urdfdom, which pinocchio uses) refuse is found here first.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

from ..diagnostics import SourceFile, Span, did_you_mean

JOINT_TYPES = ("fixed", "revolute", "continuous", "prismatic", "floating", "planar")
_VECTORS = {"origin": ("xyz", "rpy"), "axis": ("xyz",)}
_NUMBERS = {"limit": ("lower", "upper", "velocity", "effort"),
            "mimic": ("multiplier", "offset"), "mass": ("value",),
            "inertia": ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"),
            "dynamics": ("damping", "friction"), "calibration": ("rising", "falling"),
            "safety_controller": ("soft_lower_limit", "soft_upper_limit", "k_position",
                                  "k_velocity")}
_NOT_NEGATIVE = {("limit", "velocity"), ("limit", "effort"), ("mass", "value")}


class UrdfValues:
    """Checks the elements of one URDF, reporting into ``diagnostics``.

    Args:
        source: The URDF file.
        diagnostics: Where problems go.
    """

    def __init__(self, source: SourceFile, diagnostics: list):
        self.source = source
        self.lines = source.text.splitlines()
        self.diagnostics = diagnostics
        self.count = 0

    def joint(self, joint: ET.Element, line: int) -> bool:
        """Whether the joint (its element at ``line``) can be read."""
        before = self._errors()
        kind = joint.get("type", "")
        if kind not in JOINT_TYPES:
            self._error(line, f'type="{kind}"', f"joint '{joint.get('name')}' has no URDF "
                        f"type '{kind}'", did_you_mean(kind, JOINT_TYPES)
                        or "types: " + ", ".join(JOINT_TYPES))
        self.element(joint, line, f"joint '{joint.get('name')}'")
        limit = joint.find("limit")
        self._limit(joint, limit, kind, line)
        axis = joint.find("axis")
        if axis is not None and kind not in ("fixed", "floating") \
                and self._errors() == before \
                and not any(float(v) for v in axis.get("xyz", "1 0 0").split()):
            self._error(line, 'xyz="', f"joint '{joint.get('name')}' has a zero axis",
                        "the axis is a direction: for example xyz=\"0 0 1\"")
        if limit is not None and kind in ("revolute", "prismatic") \
                and self._errors() == before:
            lower, upper = float(limit.get("lower", "0")), float(limit.get("upper", "0"))
            if lower > upper:
                self._error(line, "lower=", f"joint '{joint.get('name')}' has its lower limit "
                            f"{lower:g} above its upper limit {upper:g}",
                            "swap them, or fix the one that is wrong")
        return self._errors() == before

    def _errors(self) -> int:
        return sum(d.is_error for d in self.diagnostics)

    def _limit(self, joint: ET.Element, limit: ET.Element | None, kind: str,
               line: int) -> None:
        """A revolute or prismatic joint has a ``<limit>``; every limit has a velocity
        and an effort (a missing lower or upper limit leaves that side unbounded)."""
        name = joint.get("name")
        if limit is None:
            if kind in ("revolute", "prismatic"):
                self._error(line, "<joint", f"{kind} joint '{name}' has no <limit>",
                            "add <limit lower=\"...\" upper=\"...\" velocity=\"...\" "
                            "effort=\"...\"/> (SI), or make it type=\"continuous\"")
            return
        for attribute in ("velocity", "effort"):
            if attribute not in limit.attrib:
                self._error(line, "<limit", f"the <limit> of joint '{name}' has no "
                            f"'{attribute}'", "URDF needs both velocity and effort in a "
                            "<limit> (rad/s or m/s, N m or N)")

    def unique(self, elements: list, tag: str, lines: dict) -> bool:
        """Whether no two of ``elements`` (``<link>`` or ``<joint>``) share a name."""
        seen, unique = set(), True
        for element in elements:
            name = element.get("name")
            if name in seen:
                self._error(lines.get((tag, name), 1), f'name="{name}"',
                            f"two {tag}s are named '{name}'",
                            f"the names of a URDF's {tag}s are unique: rename one", skip=1)
                unique = False
            seen.add(name)
        return unique

    def link(self, link: ET.Element, line: int) -> bool:
        """Whether the link's origins and inertial numbers can be read."""
        before = len(self.diagnostics)
        self.element(link, line, f"link '{link.get('name')}'")
        return len(self.diagnostics) == before

    def element(self, parent: ET.Element, line: int, what: str) -> None:
        """Every number under ``parent``."""
        for child in parent.iter():
            for name in _VECTORS.get(child.tag, ()):
                if name in child.attrib:
                    self._vector(child, name, line, what)
            for name in _NUMBERS.get(child.tag, ()):
                if name in child.attrib:
                    self._number(child, name, line, what)

    def _number(self, element: ET.Element, name: str, line: int, what: str) -> None:
        text = element.get(name)
        value = finite(text)
        if value is None:
            self._error(line, f'{name}="{text}"', f"'{name}' of the <{element.tag}> of {what} "
                        f"must be a finite number, not '{_shown(text)}'",
                        "URDF numbers are SI without a unit (m, rad, m/s, rad/s, N, kg)",
                        tag=element.tag)
        elif value < 0 and (element.tag, name) in _NOT_NEGATIVE:
            self._error(line, f'{name}="{text}"', f"'{name}' of the <{element.tag}> of {what} "
                        f"is negative: {text}", "a velocity, effort or mass limit is >= 0")

    def _vector(self, element: ET.Element, name: str, line: int, what: str) -> None:
        text = element.get(name)
        parts = vector_parts(text)
        if len(parts) != 3 or any(finite(p) is None for p in parts):
            self._error(line, f'{name}="{text}"', f"'{name}' of the <{element.tag}> of {what} "
                        f"must be three finite numbers, not '{_shown(text)}'",
                        "for example xyz=\"0 0 0.1\" (m) or rpy=\"0 0 1.57\" (rad)",
                        tag=element.tag)

    def _error(self, line: int, needle: str, message: str, hint: str, skip: int = 0,
               tag: str | None = None) -> None:
        found_line, column, length = self._locate(line, needle, skip, tag)
        self.diagnostics.append(self.source.error(
            "urdf-error", message, Span.point(found_line, column, length), hint))

    def _locate(self, line: int, needle: str, skip: int = 0,
                tag: str | None = None) -> tuple[int, int, int]:
        """The first place at or after ``line`` where ``needle`` is written, the first
        ``skip`` places passed over, and its length; for an attribute of a ``<tag>``
        whose value the file writes otherwise (``&#10;``), where the attribute begins
        in the first ``<tag>`` from ``line`` on."""
        found = self._find(line, needle, skip)
        if found is None and tag is not None:
            opening = self._find(line, f"<{tag}")
            attribute = needle.split('"')[0] + '"'
            if opening is not None:
                found = self._find(opening[0], attribute, column=opening[1])
                needle = attribute
        return (*found, len(needle)) if found else (line, 1, len(needle))

    def _find(self, line: int, needle: str, skip: int = 0,
              column: int = 1) -> tuple[int, int] | None:
        """``(line, column)`` of the ``skip``-th place of ``needle`` from ``line`` and
        ``column`` on (1-based), or ``None``."""
        for number in range(max(line, 1), len(self.lines) + 1):
            at = self.lines[number - 1].find(needle, column - 1 if number == line else 0)
            while at >= 0:
                if not skip:
                    return number, at + 1
                skip -= 1
                at = self.lines[number - 1].find(needle, at + 1)
        return None


def _shown(text: str) -> str:
    """``text`` as a message quotes it: a line break, a tab or a character beyond ASCII
    (a full-width digit looks like a digit) escaped."""
    return text.encode("unicode_escape").decode("ascii")


_NUMBER = re.compile(r"[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?")


def finite(text: str | None) -> float | None:
    """``text`` as a finite float, read as urdfdom reads a number (blanks before it,
    nothing after it, ASCII digits), else ``None``."""
    if text is None or not _NUMBER.fullmatch(text.lstrip(" \t\n\r\f\v")):
        return None
    value = float(text)
    return value if math.isfinite(value) else None


def vector_parts(text: str) -> list:
    """The parts of a vector attribute as urdfdom cuts it: at spaces only (a tab or a
    line break leaves a part that is no number)."""
    return [part for part in text.split(" ") if part]
