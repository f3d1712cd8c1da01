"""Figures of a logged run (PNG or SVG), like mc_rtc's log viewer: joint positions and
velocity commands with one panel per joint group, task errors with one panel per
dimension, all under a strip of the states, one row per machine.

- Joints: a panel per joint group the world declares (as the log's metadata lists
  them): the largest groups of at most ten joints that share none, in the world's
  order; the joints no such group holds are grouped by their name up to the word
  ``joint`` (``bazar_left_joint_3`` -> ``bazar_left``, ``panda_joint4`` -> ``panda``), and
  a group of more than ten joints is cut into panels of ten, so that the ten colours
  of a panel are all different.
- Task errors: a panel per unit. A column's unit is the ``unit`` of its field's
  metadata when the log gives one; else it follows from the width of the task's logged
  reference: 2 a gaze angle [rad], 3 a position [m], 6 a pose or an orientation (the
  norm of an error in metres and radians, shown apart), any other a joint posture
  [rad]; a force task's error is in newtons.
- Forces: when the run had force sensors, ``forces`` draws each sensor's force [N]
  (x, y, z: what its body exerts on the environment, world frame) in a panel of its
  own; the torques are in the log.
- The states: the strip's first row holds the mission machine's states, each further
  row one nested machine (a compound state's or a region's); the same translucent
  colour marks a state in the strip, in the legend and as a band behind every panel.
  The final state the run ended in is a marker (a diamond on the strip and a vertical
  line), not a band.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..diagnostics import RobocopError
from .log import GROUPS_KEY, check_timeseries, read_events, read_timeseries

WIDTH = 11.0             # [in] figure width
PANEL_HEIGHT = 2.3       # [in] height of one panel of signals
ROW_HEIGHT = 0.28        # [in] height of one machine's row in the states' strip
LEGEND_CHARACTERS = 150  # characters of the states' legend that fit across the figure
BAND_ALPHA = 0.3         # opacity of a state's band behind the signals, strip and legend
PANEL_LINES = 10         # at most this many joints in one panel
FIGURES = {
    "joint_positions": ("q.", "position [rad or m]"),
    "velocity_commands": ("command.", "velocity command [rad/s or m/s]"),
    "task_errors": ("error.", None),
}
ERROR_PANELS = {"m": "position error [m]", "rad": "angle error [rad]",
                "m+rad": "pose error, norm of metres and radians [m, rad]",
                "N": "force error [N]"}
FORCE_PREFIX = "force."
UNKNOWN_STEP = 1e-3      # [s] a cycle's length when the log cannot tell it (one row)
_JOINT_WORD = re.compile(r"^(.*?)_?joint", re.IGNORECASE)


def state_spans(time: np.ndarray, states: np.ndarray) -> list:
    """``(state, start, end)`` for each stretch of cycles spent in one configuration [s]."""
    spans = []
    start = 0
    for index in range(1, len(states) + 1):
        if index == len(states) or states[index] != states[start]:
            end = time[index] if index < len(states) else time[-1]
            spans.append((str(states[start]), float(time[start]), float(end)))
            start = index
    return spans


def legend_columns(names: list) -> int:
    """How many configurations the states' legend puts on one row, so that long ones
    (``both/left/above | both/right/down``) stay inside the figure."""
    longest = max((len(n) for n in names), default=1)
    return max(1, min(len(names), 8, LEGEND_CHARACTERS // (longest + 6)))


def joint_panels(joints: list, declared: dict | None = None) -> list:
    """``(title, joints)`` per panel: the ``declared`` joint groups (name -> joints)
    chosen as the module says, then the other joints grouped by their name up to
    ``joint``, in first-seen order, groups longer than :data:`PANEL_LINES` cut in
    pieces."""
    panels, covered = [], set()
    fitting = [(name, members) for name, members in (declared or {}).items()
               if len(members) <= PANEL_LINES and set(members) <= set(joints)]
    for name, members in sorted(fitting, key=lambda item: -len(item[1])):
        if not covered & set(members):
            panels.append((name, [j for j in joints if j in members]))
            covered |= set(members)
    order = {name: index for index, name in enumerate(declared or {})}
    panels.sort(key=lambda panel: order[panel[0]])
    groups: dict = {}
    for joint in (j for j in joints if j not in covered):
        match = _JOINT_WORD.match(joint)
        key = match.group(1) if match and match.group(1) else joint.rsplit("_", 1)[0]
        groups.setdefault(key, []).append(joint)
    for key, members in groups.items():
        pieces = [members[i:i + PANEL_LINES] for i in range(0, len(members), PANEL_LINES)]
        for number, piece in enumerate(pieces, start=1):
            panels.append((key if len(pieces) == 1 else f"{key} ({number})", piece))
    return panels


def error_units(data: dict, units: dict) -> dict:
    """``{error column: unit}`` (``m``, ``rad`` or ``m+rad``) for every task error."""
    found = {}
    for column in data:
        if not column.startswith("error."):
            continue
        if column in units:
            if units[column] != "m+rad" or f"{column}.position" not in data:
                found[column] = units[column]
            continue
        task = column[len("error."):]
        width = sum(1 for c in data if c.startswith(f"reference.{task}."))
        found[column] = {2: "rad", 3: "m", 6: "m+rad"}.get(width, "rad")
    return found


def machine_rows(configurations: list) -> list:
    """The machines seen in the run, the mission's (``""``) first, then nested ones in
    first-seen order. A compound state's path names its machine, a region's path
    (``both/left``) its own; a parallel state, whose active leaves go on through
    several regions at once, is no machine."""
    rows, parallel = [""], set()
    for configuration in configurations:
        below: dict = {}
        for leaf in configuration.split(" | "):
            parts = leaf.split("/")
            for depth in range(1, len(parts)):
                below.setdefault("/".join(parts[:depth]), set()).add(parts[depth])
                machine = "/".join(parts[:depth])
                if machine not in rows:
                    rows.append(machine)
        parallel |= {path for path, names in below.items() if len(names) > 1}
    return [row for row in rows if row not in parallel]


def machine_state(configuration: str, machine: str) -> str | None:
    """The name of ``machine``'s active state in ``configuration`` (``None``: inactive)."""
    for leaf in configuration.split(" | "):
        if machine == "":
            return leaf.split("/")[0]
        if leaf.startswith(machine + "/"):
            return leaf[len(machine) + 1:].split("/")[0]
    return None


def panel_colours(count: int, plt) -> list:
    """``count`` colours, all different: tab10, tab20, then evenly spread on turbo."""
    if count <= 10:
        return [plt.get_cmap("tab10")(i) for i in range(count)]
    if count <= 20:
        return [plt.get_cmap("tab20")(i) for i in range(count)]
    return [plt.get_cmap("turbo")(x) for x in np.linspace(0.05, 0.95, count)]


class PlotError(RobocopError):
    """Figures that cannot be made: a log without cycles, an output that cannot be
    written."""


def _field_units(schema) -> dict:
    """``{column: unit}`` from the ``unit`` metadata of the time series' fields."""
    return {field.name: field.metadata[b"unit"].decode() for field in schema
            if field.metadata and b"unit" in field.metadata}


def _declared_groups(schema) -> dict:
    """The joint groups the log's metadata lists (none for a log written before)."""
    import json

    metadata = schema.metadata or {}
    return json.loads(metadata[GROUPS_KEY]) if GROUPS_KEY in metadata else {}


def _final_state(folder: Path) -> tuple | None:
    """``(configuration, outcome)`` of the final state the run ended in, if any."""
    try:
        ends = [e for e in read_events(folder) if e["kind"] == "end"]
    except FileNotFoundError:
        return None
    if (ends and ends[-1].get("outcome") in ("success", "failure")
            and isinstance(ends[-1].get("state"), str)):
        return ends[-1]["state"], ends[-1]["outcome"]
    return None


def plot_run(folder: str | Path, output: str | Path | None = None,
             fmt: str = "png") -> list:
    """Write the figures of the run logged in ``folder`` as ``fmt`` (png or svg);
    return their paths. Raises as :func:`figures`, and :class:`PlotError` when
    ``output`` cannot be written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    made = figures(folder)
    output = Path(output or folder)
    written = []
    try:
        output.mkdir(parents=True, exist_ok=True)
        for name, figure in made:
            path = output / f"{name}.{fmt}"
            try:
                figure.savefig(path, dpi=110)
            finally:
                plt.close(figure)
            written.append(path)
    except FileExistsError:
        raise PlotError(f"{output}: not a folder; give a folder for the figures with "
                        "-o DIR") from None
    except OSError as error:
        raise PlotError(f"{error.filename or output}: cannot write the figures "
                        f"({error.strerror or error})") from None
    return written


def figures(folder: str | Path):
    """``(name, matplotlib figure)`` of each figure of the run logged in ``folder``,
    one at a time (the caller closes each); the log is read and checked first.

    Raises:
        FileNotFoundError: no time series there.
        UnreadableLog: a damaged log (:func:`~robocop_dsl.runtime.log.check_timeseries`,
            :func:`~robocop_dsl.runtime.log.event_lines`).
        PlotError: a log without cycles.
    """
    import matplotlib.pyplot as plt

    folder = Path(folder)
    schema = check_timeseries(folder)
    data = read_timeseries(folder)
    if not len(data["time"]):
        raise PlotError(f"{folder}: no cycle logged, nothing to plot")
    states = StateBands(data["time"], np.asarray(data["state"]).astype(str),
                        _final_state(folder), plt)
    return _figures(data, states, error_units(data, _field_units(schema)),
                    _declared_groups(schema), plt)


def _figures(data: dict, states: StateBands, units: dict, declared: dict, plt):
    for name, (prefix, label) in FIGURES.items():
        if label is None:
            panels = [(ERROR_PANELS[unit], [c for c, u in units.items() if u == unit])
                      for unit in ERROR_PANELS]
            panels = [(title, columns, title) for title, columns in panels if columns]
        else:
            joints = [c[len(prefix):] for c in data if c.startswith(prefix)]
            panels = [(title, [prefix + j for j in members], label)
                      for title, members in joint_panels(joints, declared)]
        yield name, draw(data, panels, prefix, states, plt)
    sensors = force_panels(list(data))
    if sensors:
        yield "forces", draw(data, sensors, FORCE_PREFIX, states, plt)


def force_panels(columns: list) -> list:
    """``(title, columns, y label)`` per force sensor of the log: its ``force.BODY.x|y|z``
    columns, in the log's order."""
    bodies = dict.fromkeys(c[len(FORCE_PREFIX):].rsplit(".", 1)[0] for c in columns
                           if c.startswith(FORCE_PREFIX))
    return [(f"force sensor on {body}", [f"{FORCE_PREFIX}{body}.{axis}" for axis in "xyz"],
             "force on the environment [N]") for body in bodies]


def draw(data: dict, panels: list, prefix: str, states: StateBands, plt):
    """A figure: the states' strip, then one axes per ``(title, columns, y label)``."""
    rows = len(states.rows)
    heights = [ROW_HEIGHT * rows] + [PANEL_HEIGHT] * max(len(panels), 1)
    legend_rows = -(-len(states.names) // legend_columns(states.names))
    legend_height = 0.45 + 0.2 * legend_rows
    figure, axes = plt.subplots(len(heights), 1, sharex=True, squeeze=False,
                                figsize=(WIDTH, sum(heights) + 0.6 + legend_height),
                                gridspec_kw={"height_ratios": heights})
    axes = list(axes[:, 0])
    states.draw_strip(axes[0])
    time = data["time"]
    for ax, (title, columns, label) in zip(axes[1:], panels):
        states.draw_bands(ax)
        for column, colour in zip(columns, panel_colours(len(columns), plt)):
            ax.plot(time, data[column], linewidth=1.2, color=colour,
                    label=column[len(prefix):])
        ax.set_title(title, fontsize=9, loc="left")
        ax.set_ylabel(label, fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
    if not panels:
        axes[1].text(0.5, 0.5, "nothing logged", ha="center", va="center",
                     transform=axes[1].transAxes)
    axes[-1].set_xlabel("mission time [s]")
    states.legend(figure)
    figure.tight_layout(rect=(0, legend_height / figure.get_figheight(), 1, 1))
    return figure


class StateBands:
    """The states of a run as drawn: one strip row per machine, one colour per state
    name, translucent bands, the final state as a marker."""

    def __init__(self, time: np.ndarray, configurations: np.ndarray, final, plt):
        self.plt = plt
        self.time = time
        step = float(np.median(np.diff(time))) if len(time) > 1 else 0.0
        self.end = float(time[-1]) + (step if step > 0 else UNKNOWN_STEP)
        self.final = final
        self.rows = machine_rows(list(dict.fromkeys(configurations)))
        self.spans = {machine: self._spans(configurations, machine) for machine in self.rows}
        self.names = list(dict.fromkeys(
            name for machine, spans in self.spans.items() for name, start, end in spans
            if not self._is_final(machine, name, end)))
        palette = panel_colours(len(self.names), plt)
        self.colours = dict(zip(self.names, palette))

    def _spans(self, configurations: np.ndarray, machine: str) -> list:
        """``(state name, start, end)`` [s] of ``machine``'s active states; a stretch
        ends where the next begins, the last one cycle after the last record."""
        names = [machine_state(c, machine) for c in configurations]
        spans = []
        start = 0
        for index in range(1, len(names) + 1):
            if index == len(names) or names[index] != names[start]:
                end = float(self.time[index]) if index < len(names) else self.end
                if names[start] is not None:
                    spans.append((names[start], float(self.time[start]), end))
                start = index
        return spans

    def _is_final(self, machine: str, name: str, end: float) -> bool:
        return (self.final is not None and machine == "" and end >= self.end
                and name == self.final[0].split("/")[0])

    def draw_strip(self, ax) -> None:
        for row, machine in enumerate(self.rows):
            for name, start, end in self.spans[machine]:
                if self._is_final(machine, name, end):
                    colour = "tab:green" if self.final[1] == "success" else "tab:red"
                    ax.plot([start], [row], marker="D", color=colour, markersize=7,
                            linestyle="none")
                    continue
                ax.barh(row, end - start, left=start, height=0.8,
                        color=self.colours[name], alpha=BAND_ALPHA, linewidth=0)
                if end - start > 0.06 * self.end:
                    ax.text((start + end) / 2, row, name, ha="center", va="center",
                            fontsize=7, clip_on=True)
        ax.set_yticks(range(len(self.rows)))
        ax.set_yticklabels([m or "mission" for m in self.rows], fontsize=7)
        ax.set_ylim(len(self.rows) - 0.5, -0.5)
        ax.set_xlim(0, self.end)
        ax.tick_params(axis="x", labelbottom=False)
        ax.set_title("states", fontsize=9, loc="left")

    def draw_bands(self, ax) -> None:
        """The mission machine's states behind a panel, and the final state's line."""
        for name, start, end in self.spans[""]:
            if self._is_final("", name, end):
                ax.axvline(start, color="tab:green" if self.final[1] == "success"
                           else "tab:red", linewidth=1.0, linestyle="--")
            else:
                ax.axvspan(start, end, color=self.colours[name], alpha=BAND_ALPHA,
                           linewidth=0)
        ax.set_xlim(0, self.end)

    def legend(self, figure) -> None:
        """Translucent patches like the bands, one per state drawn; the final state's
        marker."""
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        handles = [Patch(facecolor=self.colours[n], alpha=BAND_ALPHA, linewidth=0)
                   for n in self.names]
        labels = list(self.names)
        if self.final is not None:
            colour = "tab:green" if self.final[1] == "success" else "tab:red"
            handles.append(Line2D([], [], marker="D", color=colour, linestyle="none"))
            labels.append(f"{self.final[0]} (final, {self.final[1]})")
        if handles:
            figure.legend(handles, labels, loc="lower center", fontsize=8, frameon=False,
                          ncol=legend_columns(labels), title="states")
