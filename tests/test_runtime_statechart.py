"""The semantics of nested machines, behaviour instances and parallel regions, on machines
built by hand and run by the statechart alone (one cycle lasts 1 s, so times count
cycles)."""

from typing import Callable, NamedTuple

from robocop_dsl.compile import spec as s
from robocop_dsl.compile.state_graph import join
from robocop_dsl.diagnostics import Span
from robocop_dsl.runtime.build import build_machine
from robocop_dsl.runtime.program import Program
from robocop_dsl.runtime.statechart import Activation, Statechart

SPAN = Span.point(1)


def log(text):
    return s.LogAction(text, SPAN)


def emit(event):
    return s.EmitAction(event, SPAN)


def after(seconds):
    return s.CompareCondition(s.ElapsedMeasure(), ">=", seconds)


def at(seconds):
    return s.CompareCondition(s.TimeMeasure(), ">=", seconds)


def visits_below(path, count):
    return s.CompareCondition(s.VisitsMeasure(path), "<", count)


def when(condition, target, *actions, text=None):
    return s.TransitionSpec(condition, target, text or f"-> {target}", False, SPAN, actions)


def guard(condition, target, *actions, text=None):
    return s.TransitionSpec(condition, target, text or f"-> {target}", True, SPAN, actions)


class Draft(NamedTuple):
    """A state whose path is known once its machine is placed: ``build(path)``."""

    name: str
    build: Callable


def state(name, enter=(), during=(), exit=(), when=(), machines=(), parallel=False):
    """A state; ``machines`` are functions of the state's path (see :func:`machine`)."""
    return Draft(name, lambda path: s.StateSpec(
        name, tuple(enter), tuple(during), tuple(exit), tuple(when), False, None, SPAN,
        path=path, machines=tuple(m(path) for m in machines), parallel=parallel))


def final(name, outcome="success", enter=()):
    return Draft(name, lambda path: s.StateSpec(name, tuple(enter), (), (), (), True,
                                                outcome, SPAN, path=path))


def machine(*states, guards=(), region=None):
    """A function of the path of the state it belongs to (``""``: the mission) giving the
    machine of ``states``, starting in the first; a region adds its name to the path."""
    def make(path):
        path = join(path, region) if region else path
        built = {d.name: d.build(join(path, d.name)) for d in states}
        return s.MachineSpec(path, built, states[0].name, tuple(guards), region)
    return make


def region(name, *states, guards=()):
    return machine(*states, guards=guards, region=name)


class Context:
    """What actions and clause tests read: time [s] (one cycle is 1 s), cycle, chart;
    ``lines`` keeps logs and transitions, with their cycle."""

    def __init__(self, root):
        self.program = Program(build_machine(root("")))
        self.chart = Statechart(self.program, self.on_transition)
        self.cycle = 0
        self.failed = False
        self.lines = []

    @property
    def time(self):
        return float(self.cycle)

    def log(self, text):
        self.lines.append((self.cycle, text))

    def emit(self, event):
        self.chart.raise_event(event, self.cycle)

    def on_transition(self, source, target, condition):
        self.lines.append((self.cycle, f"{source} -> {target}"))

    def start(self):
        return self.chart.start(self)

    def step(self):
        """One cycle: transitions, then during blocks; the cycle's :class:`MacroStep`."""
        macro = self.chart.transitions(self)
        if macro.outcome is None:
            self.chart.during(self)
        self.cycle += 1
        return macro

    def run(self, cycles):
        return [self.step() for _ in range(cycles)]

    def logged(self, cycle=None):
        return [text for c, text in self.lines if cycle is None or c == cycle]


def blocks(name):
    """Enter, during and exit blocks that log their state's name."""
    return {"enter": [log(f"enter {name}")], "during": [log(f"during {name}")],
            "exit": [log(f"exit {name}")]}


THREE_LEVELS = machine(
    state("outer", **blocks("outer"), machines=[machine(
        state("mid", **blocks("mid"), machines=[machine(
            state("inner", **blocks("inner")))])
    )], when=[when(after(2), "other", log("act"))]),
    state("other", **blocks("other"), when=[when(after(1), "done")]),
    final("done"))


def test_enter_exit_during_and_actions_across_three_levels():
    """Enter outermost first, during outermost first, exit innermost first, the clause's
    actions between the exits and the enters."""
    context = Context(THREE_LEVELS)
    start = context.start()
    assert context.logged() == ["enter outer", "enter mid", "enter inner"]
    assert start.entered == ("outer", "outer/mid", "outer/mid/inner")
    assert start.configuration == "outer/mid/inner"
    context.run(2)
    assert context.logged(1) == ["during outer", "during mid", "during inner"]
    macro = context.step()
    assert context.logged(2) == ["outer -> other", "exit inner", "exit mid", "exit outer",
                                 "act", "enter other", "during other"]
    assert [(m.source, m.target) for m in macro.steps] == [("outer", "other")]
    assert macro.exited == ("outer/mid/inner", "outer/mid", "outer")
    assert macro.entered == ("other",)
    assert macro.configuration == "other" and macro.outcome is None
    macro = context.step()
    assert (macro.final, macro.outcome, macro.configuration) == ("done", "success", "done")


def test_the_configuration_before_the_start_is_the_start_configuration():
    context = Context(THREE_LEVELS)
    assert context.chart.configuration == "outer/mid/inner"
    assert context.chart.active() == ()
    context.start()
    assert context.chart.active() == ("outer", "outer/mid", "outer/mid/inner")


def test_inner_clauses_come_before_outer_ones():
    """In cycle 2 the inner state's clause and the outer state's clause both hold: only
    the inner one fires; the outer one fires in the next cycle, when nothing inside
    does. The mission's guard, true from cycle 2 on, comes after both."""
    context = Context(machine(
        state("pick", machines=[machine(
            state("above", when=[when(after(2), "down")]),
            state("down", when=[when(after(5), "above")]))],
            when=[when(after(2), "carry", text="pick clause")]),
        state("carry", when=[when(after(10), "failed")]),
        final("failed", "failure"),
        guards=[guard(at(2), "failed", text="mission guard")]))
    context.start()
    macros = context.run(4)
    assert [[(m.source, m.target) for m in macro.steps] for macro in macros] == [
        [], [], [("pick/above", "pick/down")], [("pick", "carry")]]
    assert context.step().steps[0].condition == "mission guard"


def test_a_machine_guard_comes_after_its_state_clauses_and_before_the_parent():
    """``pick``'s guard (elapsed >= 3 s in its active state) fires in cycle 3, when the
    active state ``above``'s own clause (5 s) does not, before ``pick``'s own clause."""
    context = Context(machine(
        state("pick", machines=[machine(
            state("above", when=[when(after(5), "down")]),
            state("down"),
            guards=[guard(after(3), "down", text="pick guard")])],
            when=[when(after(3), "carry", text="pick clause")]),
        state("carry")))
    context.start()
    macros = context.run(5)
    fired = [(macro.cycle, m.condition) for macro in macros for m in macro.steps]
    assert fired == [(3, "pick guard"), (4, "pick clause")]


def test_elapsed_in_a_guard_counts_from_the_active_state_entry():
    """A machine's guard ``elapsed >= 3 s`` restarts when the active state changes."""
    context = Context(machine(
        state("pick", machines=[machine(
            state("above", when=[when(after(2), "down")]),
            state("down"),
            final("missed"),
            guards=[guard(after(3), "missed")])],
            when=[when(s.FinalCondition("pick", "missed"), "carry")]),
        state("carry")))
    context.start()
    macros = context.run(7)
    fired = [(macro.cycle, m.source, m.target) for macro in macros for m in macro.steps]
    assert fired == [(2, "pick/above", "pick/down"), (5, "pick/down", "pick/missed"),
                     (6, "pick", "carry")]


def test_elapsed_in_a_state_clause_counts_from_that_state_entry():
    """The outer state's ``elapsed`` ignores the changes inside it."""
    context = Context(machine(
        state("pick", machines=[machine(
            state("above", when=[when(after(2), "down")]),
            state("down", when=[when(after(2), "above")]))],
            when=[when(after(5), "carry")]),
        state("carry")))
    context.start()
    macros = context.run(6)
    assert [(m.cycle, m.configuration) for m in macros] == [
        (0, "pick/above"), (1, "pick/above"), (2, "pick/down"), (3, "pick/down"),
        (4, "pick/above"), (5, "carry")]


def parallel(timeout):
    """``both``: two regions, the left arrives in cycle 4, the right in cycle 5."""
    return machine(
        state("both", **blocks("both"), machines=[
            region("left",
                   state("above", **blocks("left/above"), when=[when(after(2), "down")]),
                   state("down", **blocks("left/down"), when=[when(after(2), "arrived")]),
                   final("arrived")),
            region("right",
                   state("above", **blocks("right/above"), when=[when(after(2), "down")]),
                   state("down", **blocks("right/down"), when=[when(after(3), "arrived")]),
                   final("arrived"))],
            parallel=True,
            when=[when(s.DoneCondition("both"), "finish", log("both done")),
                  when(after(timeout), "failed", text="timeout")]),
        final("finish"), final("failed", "failure"))


def test_regions_step_in_order_and_may_both_fire_in_one_cycle():
    """Both regions fire in cycle 2, left first; the parallel state's own timeout, true
    too, waits for the next cycle: a region fired. Leaving exits the regions in reverse
    declaration order, then the parallel state."""
    context = Context(parallel(timeout=2))
    context.start()
    assert context.logged(0) == ["enter both", "enter left/above", "enter right/above"]
    context.run(2)
    assert context.logged(1) == ["during both", "during left/above", "during right/above"]
    macro = context.step()
    assert [(m.source, m.target) for m in macro.steps] == [
        ("both/left/above", "both/left/down"), ("both/right/above", "both/right/down")]
    assert macro.configuration == "both/left/down | both/right/down"
    assert context.logged(2)[:6] == [
        "both/left/above -> both/left/down", "exit left/above", "enter left/down",
        "both/right/above -> both/right/down", "exit right/above", "enter right/down"]
    assert context.chart.active() == ("both", "both/left/down", "both/right/down")
    macro = context.step()
    assert [m.condition for m in macro.steps] == ["timeout"]
    assert macro.exited == ("both/right/down", "both/left/down", "both")
    assert context.logged(3) == ["both -> failed", "exit right/down", "exit left/down",
                                 "exit both"]
    assert macro.outcome == "failure"


def test_a_parallel_state_waits_for_every_region():
    """``S.REGION.FINAL`` holds as soon as that region arrives, ``S.done`` once both have
    (checked in the next cycle: a region fired in that one)."""
    context = Context(parallel(timeout=10))
    context.start()
    macros = context.run(5)
    assert macros[-1].configuration == "both/left/arrived | both/right/down"
    chart = context.chart
    assert chart.in_final("both", "arrived", "left")
    assert not chart.in_final("both", "arrived", "right") and not chart.done("both")
    assert context.step().configuration == "both/left/arrived | both/right/arrived"
    assert chart.done("both")
    macro = context.step()
    assert [(m.source, m.target) for m in macro.steps] == [("both", "finish")]
    assert macro.exited == ("both/right/arrived", "both/left/arrived", "both")
    assert context.logged(6) == ["both -> finish", "exit both", "both done"]
    assert macro.outcome == "success" and not chart.done("both")


VISITS = machine(
    state("pick", machines=[machine(
        state("try", when=[when(after(1), "wait")]),
        state("wait", when=[when(visits_below("pick/try", 3), "try", text="again"),
                            when(at(0), "missed")]),
        final("missed"))],
        when=[when(s.AllCondition((s.FinalCondition("pick", "missed"),
                                   visits_below("pick", 2))), "pick", text="retry"),
              when(s.FinalCondition("pick", "missed"), "failed")]),
    final("failed", "failure"))


def test_visits_count_re_entries_and_reset_with_their_machine():
    """``try`` is entered three times per entry of ``pick``; re-entering ``pick`` (a
    self-transition) counts its second visit and starts ``try``'s count again."""
    context = Context(VISITS)
    context.start()
    chart = context.chart
    assert (chart.visits("pick"), chart.visits("pick/try")) == (1, 1)
    macros = context.run(7)
    assert [m.configuration for m in macros[:6]] == [
        "pick/try", "pick/wait", "pick/try", "pick/wait", "pick/try", "pick/wait"]
    assert chart.visits("pick/try") == 3 and macros[6].configuration == "pick/missed"
    retry = context.step()
    assert [m.condition for m in retry.steps] == ["retry"]
    assert retry.exited == ("pick/missed", "pick") and retry.entered == ("pick", "pick/try")
    assert (chart.visits("pick"), chart.visits("pick/try"), chart.visits("pick/wait")) == (
        2, 1, 0)
    macros = context.run(8)
    assert macros[-1].final == "failed" and chart.visits("pick") == 2


def test_a_nested_final_state_does_not_end_the_run():
    context = Context(VISITS)
    context.start()
    macros = context.run(7)
    assert macros[-1].configuration == "pick/missed"
    assert all(m.outcome is None for m in macros) and context.chart.outcome is None


def talking(*listener):
    """A parallel state ``top``: region ``talker`` raises ``go`` in cycle 2, region
    ``listener`` has the states ``listener``."""
    return machine(state("top", parallel=True, machines=[
        region("talker", state("quiet", when=[when(after(2), "loud")]),
               state("loud", enter=[emit("go")])),
        region("listener", *listener)]))


def heard(*conditions):
    return s.AllCondition((s.EventCondition("go"), *conditions))


def fired_targets(macros):
    return [(m.cycle, step.target) for m in macros for step in m.steps]


def test_an_event_is_seen_from_the_cycle_after_its_raise():
    """Raised in cycle 2 by the first region, ``go`` is not seen by the second region in
    cycle 2, even though it steps after the first; it is in cycle 3."""
    context = Context(talking(state("wait", when=[when(heard(), "heard")]), final("heard")))
    context.start()
    assert fired_targets(context.run(4)) == [(2, "top/talker/loud"),
                                             (3, "top/listener/heard")]


def test_events_are_latched_until_their_owner_is_left():
    """``go`` raised in cycle 2 is still seen in cycle 5 by a state entered before."""
    context = Context(talking(state("wait", when=[when(heard(after(5)), "heard")]),
                              final("heard")))
    context.start()
    assert fired_targets(context.run(6)) == [(2, "top/talker/loud"),
                                             (5, "top/listener/heard")]


def test_a_state_entered_after_the_raise_does_not_see_the_event():
    context = Context(talking(
        state("early", when=[when(after(4), "late")]),
        state("late", when=[when(heard(), "heard"), when(after(3), "deaf")]),
        final("heard"), final("deaf")))
    context.start()
    assert fired_targets(context.run(8)) == [(2, "top/talker/loud"), (4, "top/listener/late"),
                                             (7, "top/listener/deaf")]


def test_an_earlier_raise_stays_seen_when_the_event_is_raised_again():
    """Raised in cycles 1 and 3: in cycle 3 the raise of cycle 1 is seen, by an owner
    entered before it, not by one entered in cycle 2."""
    chart = Context(machine(state("a"))).chart
    chart.raise_event("go", 1)
    chart.raise_event("go", 3)
    early, late = Activation("a", 0.0, 0), Activation("a", 2.0, 2)
    assert not chart.seen("go", early, 1)
    assert chart.seen("go", early, 2) and chart.seen("go", early, 3)
    assert not chart.seen("go", late, 3) and chart.seen("go", late, 4)


def test_a_self_transition_leaves_and_re_enters():
    context = Context(machine(
        state("loop", **blocks("loop"), when=[when(after(1), "loop", log("again"))])))
    context.start()
    context.run(2)
    assert context.logged(1) == ["loop -> loop", "exit loop", "again", "enter loop",
                                 "during loop"]
    assert context.chart.visits("loop") == 2
    assert context.chart.activation("loop").cycle == 1


def test_failure_handlers_are_those_of_the_active_configuration():
    """``controller.failed`` is handled while a checked clause tests it: the active
    states' own clauses and their machines' guards, not a final nested machine's."""
    failed = s.ControllerFailedCondition()
    context = Context(machine(
        state("pick", machines=[machine(
            state("above", when=[when(after(1), "down")]),
            state("down", when=[when(after(1), "arrived")]),
            final("arrived"),
            guards=[guard(s.AllCondition((failed, at(0))), "arrived")])],
            when=[when(s.FinalCondition("pick", "arrived"), "carry")]),
        state("carry", when=[when(failed, "carry")]),
        state("idle")))
    chart = context.chart
    context.start()
    assert chart.handles_failure()
    context.run(3)
    assert chart.configuration == "pick/arrived" and not chart.handles_failure()
    context.run(1)
    assert chart.configuration == "carry" and chart.handles_failure()

