"""PNG figures of a logged run, with a coloured band per active configuration (like
mc_rtc's log viewer): joint positions, velocity commands and task errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .log import read_timeseries

WIDTH = 11.0             # [in] figure width
LEGEND_CHARACTERS = 150  # characters of the states' legend that fit across the figure
FIGURES = {
    "joint_positions.png": ("q.", "joint positions [rad or m]"),
    "velocity_commands.png": ("command.", "velocity command [rad/s or m/s]"),
    "task_errors.png": ("error.", "task error [m or rad]"),
}


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


def plot_run(folder: str | Path, output: str | Path | None = None) -> list:
    """Write the figures of the run logged in ``folder``; return their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = read_timeseries(folder)
    output = Path(output or folder)
    output.mkdir(parents=True, exist_ok=True)
    time, states = data["time"], np.asarray(data["state"]).astype(str)
    spans = state_spans(time, states) if len(time) else []
    names = list(dict.fromkeys(s for s, _, _ in spans))
    palette = plt.get_cmap("tab20")
    colours = {name: palette(i % 20) for i, name in enumerate(names)}
    columns = legend_columns(names)
    rows = -(-len(names) // columns)
    height = 5.5 + 0.22 * rows
    written = []
    for filename, (prefix, label) in FIGURES.items():
        signals = [c for c in data if c.startswith(prefix)]
        figure, axes = plt.subplots(figsize=(WIDTH, height))
        for state, start, end in spans:
            axes.axvspan(start, end, color=colours[state], alpha=0.18, linewidth=0)
        for column in signals:
            axes.plot(time, data[column], linewidth=1.2, label=column[len(prefix):])
        axes.set_xlabel("mission time [s]")
        axes.set_ylabel(label)
        axes.grid(alpha=0.3)
        if signals:
            axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7,
                        title="signals")
        bands = [plt.Rectangle((0, 0), 1, 1, color=colours[n], alpha=0.35) for n in names]
        if bands:
            figure.legend(bands, names, loc="lower center", ncol=columns, fontsize=8,
                          title="states", frameon=False)
        figure.tight_layout(rect=(0, (0.45 + 0.17 * rows) / height if bands else 0, 1, 1))
        path = output / filename
        figure.savefig(path, dpi=110)
        plt.close(figure)
        written.append(path)
    return written
