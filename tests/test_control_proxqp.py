"""ProxQP on the controller's real problems: many inequality rows, damped Hessians."""

from pathlib import Path

from robocop_dsl.control.solvers.proxqp import ProxqpSolver
from robocop_dsl.runtime import load_mission

PICKUP = Path(__file__).resolve().parents[1] / "missions" / "pickup.mission"


def test_pickup_problems_take_a_handful_of_iterations():
    """Every QP of the pick-and-place mission (strict hierarchy, 16 dofs, collision
    avoidance reserving rows beside joint and tool limits: more than twice as many rows
    as dofs), solved again from a cold start, takes a handful of iterations. ProxQP's
    automatic factorisation took thousands on some of them (seconds for one cycle)."""
    runner = load_mission(PICKUP).runner()
    runner.start()
    iterations, widest = [], 0.0
    while runner.step():
        for problem in runner.controller.problems:
            n, _, rows = problem.size
            widest = max(widest, rows / n)
            solution = ProxqpSolver().solve(problem)
            assert solution.found
            iterations.append(solution.iterations)
    assert runner.finish().outcome == "success"
    assert widest >= 2.0
    assert len(iterations) > 2000
    assert max(iterations) <= 100
