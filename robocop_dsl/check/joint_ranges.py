"""The position ranges of the ``joint_kinematic`` constraints enabled in the first
cycle, taken together: a joint that two of them leave no position makes the run refuse
its first cycle ("no QP solution"). One constraint against the URDF is checked with its
parameters (:func:`~robocop_dsl.check.parameters.check_order`)."""

from __future__ import annotations

from ..lang import ast
from .context import CheckContext
from .enabled import enabled_from_start


def check_joint_ranges(ctx: CheckContext, mission: ast.Mission) -> None:
    """Report, at the later of the two, a pair of ``joint_kinematic`` constraints enabled
    in the first cycle (from the start, or by the start state's ``enter``, and not
    disabled by it) whose declared ``min_position`` and ``max_position`` leave a joint no
    position [rad or m]. Values that actions assign are compared within their constraint
    only (:mod:`.assigned_limits`)."""
    if not ctx.world.known:
        return
    enabled, disabled = _switched_on_entry(mission)
    enabled |= enabled_from_start(mission) - disabled
    lowest: dict[str, tuple[float, ast.ConstraintDecl]] = {}
    highest: dict[str, tuple[float, ast.ConstraintDecl]] = {}
    reported: set = set()
    for decl in mission.constraints:
        if (decl.kind.text != "joint_kinematic" or decl.name.text not in enabled
                or len(decl.arguments) != 1):
            continue
        group = decl.arguments[0].text
        if not ctx.world.has_joints(group):
            continue
        numbers = ctx.declared.get(decl.name.text, {})
        infos = ctx.world.world.moving_joints(group)
        for side, found, better in (("min_position", lowest, float.__gt__),
                                    ("max_position", highest, float.__lt__)):
            values = numbers.get(side, (None, None))[1]
            for index, info in enumerate(infos if values is not None else ()):
                if info.name not in found or better(float(values[index]), found[info.name][0]):
                    found[info.name] = (float(values[index]), decl)
        for info in infos:
            low, high = lowest.get(info.name), highest.get(info.name)
            if (low is None or high is None or low[0] <= high[0] or low[1] is high[1]
                    or (low[1].name.text, high[1].name.text) in reported):
                continue
            reported.add((low[1].name.text, high[1].name.text))
            unit = "m" if info.type == "prismatic" else "rad"
            other = high[1] if low[1] is decl else low[1]
            ctx.error("inverted-limits", f"constraints '{other.name.text}' and "
                      f"'{decl.name.text}' leave joint '{info.name}' no position: "
                      f"min_position {low[0]:.4g} {unit} of '{low[1].name.text}' is above "
                      f"max_position {high[0]:.4g} {unit} of '{high[1].name.text}'",
                      decl.name.span, "both are enabled in the first cycle: make their "
                      "ranges overlap, or enable one only where the other is disabled")


def _switched_on_entry(mission: ast.Mission) -> tuple[set[str], set[str]]:
    """What the start state's ``enter`` block leaves enabled and disabled (in order)."""
    start = mission.first(ast.StartDecl)
    state = next((s for s in mission.states if start and s.name.text == start.state.text),
                 None)
    enabled: set[str] = set()
    disabled: set[str] = set()
    for block in state.blocks if state else ():
        for action in block.actions if block.kind == "enter" else ():
            if isinstance(action, (ast.Enable, ast.Disable)):
                names = {name.text for name in action.names}
                on, off = (enabled, disabled) if isinstance(action, ast.Enable) else (
                    disabled, enabled)
                on |= names
                off -= names
    return enabled, disabled
