"""DAQP called directly against ProxQP on the controller's QPs, the ``auto`` rule, and
``solver: daqp`` / ``solver: auto`` through a real mission."""

import inspect
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from robocop_dsl.cli.main import main
from robocop_dsl.control import Controller
from robocop_dsl.control.solvers import (QuadraticProgram, available_solvers,
                                         braking_solver, level_solvers, make_solver)
from robocop_dsl.control.solvers.choice import choose, level_backends
from robocop_dsl.control.solvers.daqp_direct import DaqpSolver
from robocop_dsl.control.solvers.proxqp import ProxqpSolver
from robocop_dsl.control.solvers.qpsolvers_backend import QpsolversSolver
from robocop_dsl.world import load_world
from robocop_dsl.world.processors import PROCESSOR_TYPES

REPO = Path(__file__).resolve().parent.parent
CASES = {
    "Panda": ("panda/panda_on_table.yaml", "panda_arm", 0.002, ("panda_hand",), False),
    "BAZAR": ("bazar/sophia.yaml", "bazar_upper_joints", 0.005,
              ("bazar_left_hankamp_tool_object_side", "bazar_right_hankamp_tool_object_side"),
              True),
}
TOLERANCE = 1e-6
"""[rad/s] Largest difference between the two solvers' commands."""


def controller(name, hierarchy, shift, solver="proxqp"):
    """The case's controller with body_pose targets ``shift`` [m] away (0.6: out of
    reach, joints driven into their limits), a posture task at priority 1."""
    path, group, time_step, bodies, body_velocity = CASES[name]
    world = load_world(path)
    q0 = world.initial_configuration()
    control = Controller(world, group, time_step, solver, hierarchy, damping=1e-6)
    control.add_constraint("joint_kinematic", "limits", group, max_acceleration=10.0)
    if body_velocity:
        for body in bodies:
            control.add_constraint("body_velocity", f"{body}_speed", body, max_linear=0.5,
                                   max_angular=1.0)
    control.set_auto_enable(True)
    offset = pin.SE3(pin.exp3(np.array([0.0, 0.0, 0.2])), np.array([shift, -shift, shift]))
    for body in bodies:
        control.add_task("body_pose", body, body, target=world.body_pose(body, q0) * offset,
                         gain=5.0)
    control.add_task("joint_position", "posture", group, priority=1, weight=1e-2, gain=5.0,
                     target=q0[control.state.q_indices])
    return control, q0, world.joint_group(group).q_indices, time_step


def quadprog(program):
    """``program``'s solution by quadprog (Goldfarb-Idnani), through qpsolvers."""
    solution = QpsolversSolver("quadprog").solve(program)
    assert solution.found
    return solution.x


def cost(program, x) -> float:
    return 0.5 * x @ program.H @ x + program.g @ x


@pytest.mark.parametrize("name, hierarchy, shift", [
    ("Panda", "weighted", 0.6), ("Panda", "strict", 0.05), ("Panda", "strict", 0.6),
    ("BAZAR", "weighted", 0.05), ("BAZAR", "strict", 0.6)])
def test_daqp_gives_proxqp_commands_on_the_controller_qps(name, hierarchy, shift):
    """Every level's QP (equality rows on the strict levels below the first, joint
    limits and body velocity rows) solved by DAQP gives ProxQP's command (quadprog's
    on a strict first level, ProxQP's then only as cheap)."""
    control, q, indices, time_step = controller(name, hierarchy, shift)
    solvers, bound, equality_rows, velocity_rows = {}, 0, 0, 0
    for _ in range(300):
        result = control.compute(q)
        q[indices] += result.velocity * time_step
        for level, program in zip(result.levels, control.problems):
            daqp = solvers.setdefault(level.priority, DaqpSolver()).solve(program)
            assert daqp.found and program.violation(daqp.x) <= 1e-9
            if hierarchy == "strict" and level.priority == 0:
                # the Hessian is singular but for the damping: ProxQP's tolerance leaves
                # up to 1e-3 rad/s along the singular directions (its cost up to 5e-6
                # above the optimum), where DAQP and quadprog factorise it exactly
                assert np.max(np.abs(daqp.x - quadprog(program))) <= TOLERANCE
                assert cost(program, level.command) >= cost(program, daqp.x) - 1e-9
            else:
                assert np.max(np.abs(daqp.x - level.command)) <= TOLERANCE
            bound += np.count_nonzero(np.minimum(daqp.x - program.lower,
                                                 program.upper - daqp.x) < 1e-9)
            equality_rows += program.b.size
            velocity_rows += program.l.size
    assert bound > 0
    assert (equality_rows > 0) == (hierarchy == "strict")
    assert (velocity_rows > 0) == (name == "BAZAR")


def test_daqp_keeps_its_working_set_and_repeats_bit_for_bit():
    """A warm start takes fewer iterations than the first solve, and two runs give
    the same commands to the bit."""
    runs = []
    for _ in range(2):
        control, q, indices, time_step = controller("BAZAR", "strict", 0.6, "daqp")
        commands = []
        for _ in range(200):
            command = control.compute(q).velocity
            commands.append(command.copy())
            q[indices] += command * time_step
        runs.append(np.array(commands))
    assert np.array_equal(runs[0], runs[1])
    program = control.problems[0]
    cold, warm = DaqpSolver(), DaqpSolver()
    warm.solve(program)
    assert warm.solve(program).iterations < cold.solve(program).iterations


def box(n=3, lower=-1.0, upper=1.0, rows=None, l=None, u=None, A=None, b=None):
    """A QP ``min 1/2 |x|^2 - x.1`` with the given bounds and rows."""
    C = np.zeros((0, n)) if rows is None else np.asarray(rows, float)
    A = np.zeros((0, n)) if A is None else np.asarray(A, float)
    return QuadraticProgram(np.eye(n), -np.ones(n), A,
                            np.zeros(0) if b is None else np.asarray(b, float), C,
                            np.zeros(len(C)) if l is None else np.asarray(l, float),
                            np.zeros(len(C)) if u is None else np.asarray(u, float),
                            np.full(n, lower), np.full(n, upper))


def test_infeasible_programs_are_answered_not_found():
    """Crossed bounds, rows the box cannot meet, inconsistent equalities and a NaN in
    the Hessian give found=False with DAQP's status, without an exception; the solver
    then solves a feasible program."""
    solver = DaqpSolver()
    problems = [box(lower=1.0, upper=-1.0),
                box(rows=[[1, 1, 1]], l=[5.0], u=[np.inf]),
                box(A=[[1, 0, 0], [1, 0, 0]], b=[0.5, -0.5])]
    for problem, status in zip(problems, ("infeasible", "infeasible",
                                          "overdetermined_initial")):
        for _ in range(2):
            solution = solver.solve(problem)
            assert not solution.found and solution.status == status
            assert np.array_equal(solution.x, np.zeros(3))
    broken = box()
    broken.H[0, 0] = np.nan
    assert solver.solve(broken).status == "not finite"
    feasible = box(rows=[[1, 1, 1]], l=[-np.inf], u=[1.5], A=[[1, -1, 0]], b=[0.0])
    solution = solver.solve(feasible)
    assert solution.found and solution.status == "solved"
    assert np.allclose(solution.x, [0.5, 0.5, 0.5])


def test_rule_picks_daqp_unless_the_equality_rows_reach_the_dofs():
    """DAQP while the equality rows are fewer than the dofs, ProxQP from there; DAQP
    warm-started for the braking QP; a named solver overrides the rule."""
    assert choose(7, 0) == choose(7, 6) == "daqp"
    assert choose(7, 7) == choose(16, 31) == "proxqp"
    assert level_backends([[6], [7], [3]], 7) == ["daqp", "daqp", "proxqp"]
    assert level_backends([[6, 6], [16]], 16) == ["daqp", "daqp"]
    assert [type(s) for s in level_solvers("auto", [[6], [7], [3]], 7)] == [
        DaqpSolver, DaqpSolver, ProxqpSolver]
    assert [type(s) for s in level_solvers("proxqp", [[6], [7]], 7)] == [ProxqpSolver] * 2
    assert [s.name for s in level_solvers("quadprog", [[6]], 7)] == ["quadprog"]
    braking = braking_solver("auto")
    assert isinstance(braking, DaqpSolver) and braking.warm_start
    assert not braking_solver("proxqp").warm_start
    assert isinstance(make_solver("daqp"), DaqpSolver)
    assert {"auto", "daqp", "proxqp"} <= set(available_solvers())
    assert inspect.signature(Controller).parameters["solver"].default == "auto"
    assert PROCESSOR_TYPES["qp_controller"].options["solver"].default == "auto"


def test_auto_solves_a_strict_hierarchy_with_more_task_rows_than_dofs():
    """Panda (7 dofs) with four levels, the last two with 13 and 16 equality rows: those
    on ProxQP, every level solved every cycle."""
    control, q, indices, time_step = controller("Panda", "strict", 0.6, "auto")
    control.add_task("body_position", "lift", "panda_hand", priority=2, gain=5.0,
                     target=control.world.body_pose("panda_hand", q).translation + 0.1)
    control.add_task("joint_position", "spread", "panda_arm", priority=3, gain=5.0,
                     target=q[control.state.q_indices] + 0.3)
    for _ in range(200):
        result = control.compute(q)
        assert [level.solved for level in result.levels] == [True] * 4
        q[indices] += result.velocity * time_step
    assert [type(level.solver) for level in control._cached_plan.hierarchy._levels] == [
        DaqpSolver, DaqpSolver, ProxqpSolver, ProxqpSolver]


@pytest.mark.parametrize("solver", ["daqp", "proxqp"])
def test_world_solver_option_runs_the_pickup_mission(solver, tmp_path, capsys):
    """``solver: daqp`` and ``solver: proxqp`` in the world file instead of its ``auto``:
    check accepts them, and missions/pickup.mission runs to success without a QP
    failure."""
    world = (REPO / "robots/bazar/sophia.yaml").read_text()
    assert "solver: auto" in world
    path = tmp_path / "sophia.yaml"
    path.write_text(world.replace("solver: auto", f"solver: {solver}"))
    mission = str(REPO / "missions/pickup.mission")
    assert main(["check", mission, "--world", str(path)]) == 0
    assert main(["run", mission, "--world", str(path)]) == 0
    out = capsys.readouterr().out
    assert "outcome: success" in out and "QP failures: 0" in out
