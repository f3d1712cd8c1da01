"""The progress of ``sweep`` when its output is not a terminal (a pipe, a CI log): a
line every N jobs and one at the end, with the count of each outcome, the running
success rate, the time elapsed and the estimated time left; the bar on a terminal."""

import io
import re

from robocop_dsl.cli.sweep_progress import SweepProgress

from conftest import MISSIONS
from test_campaign_engine import small_campaign, sweep_command

LINE = re.compile(r"^(\d+)/(\d+) jobs  success rate ([\d.]+) %  (.*)  "
                  r"elapsed \d+:\d\d:\d\d  ETA \d+:\d\d:\d\d$")

ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]")


class Terminal(io.StringIO):
    def isatty(self):
        return True


def progress_lines(outcomes, every=None):
    stream = io.StringIO()
    with SweepProgress(len(outcomes), stream, every=every) as progress:
        for outcome in outcomes:
            progress.update({"outcome": outcome})
    return [LINE.match(line).groups() for line in stream.getvalue().splitlines()]


def test_a_line_per_tenth_with_counts_and_success_rate():
    """Twenty jobs: a line every two, each with the counts and the rate so far."""
    outcomes = ["success", "failure", "success", "success", "timeout"] * 4
    lines = progress_lines(outcomes)
    assert [int(done) for done, *_ in lines] == list(range(2, 21, 2))
    assert all(total == "20" for _, total, *_ in lines)
    assert lines[1] == ("4", "20", "75.0", "failure 1  success 3")
    assert lines[-1] == ("20", "20", "60.0", "failure 4  success 12  timeout 4")


def test_every_n_jobs_and_the_last_one():
    """A line every 5 jobs of 12, and one for the 12th."""
    lines = progress_lines(["success"] * 11 + ["error"], every=5)
    assert [(done, rate, counts) for done, _, rate, counts in lines] == [
        ("5", "100.0", "success 5"), ("10", "100.0", "success 10"),
        ("12", "91.7", "error 1  success 11")]


def test_a_terminal_gets_the_bar(monkeypatch):
    """On a terminal: the bar, the count, the rate, the outcomes and the ETA."""
    monkeypatch.setenv("COLUMNS", "160")
    stream = Terminal()
    with SweepProgress(3, stream) as progress:
        for outcome in ("success", "failure", "success"):
            progress.update({"outcome": outcome})
    last = ANSI.sub("", stream.getvalue()).split("\r")[-1]
    assert re.search(r"jobs \S+ 3/3 success rate 66.7 % failure 1  success 2 elapsed "
                     r"\d+:\d\d:\d\d  ETA 0:00:00", last), last


def test_sweep_prints_progress_beside_its_output(tmp_path, capsys):
    """A real sweep into a pipe: progress lines on standard error, the usual report on
    standard output."""
    path = small_campaign(tmp_path, [str(MISSIONS / "pickup.mission")], samples=2,
                          extra="duration: 0.5 s\n")
    assert sweep_command(path, "--serial", "--output", tmp_path / "results.parquet") == 1
    out, err = capsys.readouterr()
    assert [LINE.match(line).groups() for line in err.splitlines()] == [
        ("1", "2", "0.0", "stopped 1"), ("2", "2", "0.0", "stopped 2")]
    assert out.startswith("small: 2 jobs on serial, in this process\n")
    assert "2 of 2 jobs in " in out
