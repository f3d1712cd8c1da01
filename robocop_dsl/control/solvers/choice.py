"""``solver: auto``: one backend per QP, picked from its size and place in the hierarchy.

The rule: DAQP (:class:`~.daqp_direct.DaqpSolver`, called directly, warm-started from
the last working set) for every QP whose equality rows are fewer than its variables:
the weighted QP, the first level of a strict hierarchy, the lower levels while the
task rows of the levels above number fewer than the dofs, and the braking QP. ProxQP
(:class:`~.proxqp.ProxqpSolver`) for a strict level whose equality rows number at
least the dofs: they are then linearly dependent (consistent only up to rounding), and
DAQP, which keeps every equality row in its working set, answers "overdetermined" when
the rounding exceeds its tolerance, where ProxQP's proximal steps tolerate it.

The figures (``python bench/qp_backends.py --cycles 600``: Panda 7 dofs, BAZAR 16 dofs
with 52 body velocity rows, TALOS 30 dofs; targets within reach and out of reach, the
joints then at their limits; thread CPU time per solve, each solver kept for its QP
from cycle to cycle, the backends in turns on the same QPs; DAQP's time over
ProxQP's, below 1: DAQP is faster):

- DAQP is faster on every QP measured, whatever its size and the number of rows
  binding: 0.55-0.89 (Panda), 0.55-0.98 (BAZAR), 0.39-0.91 (TALOS) on the levels,
  0.21-0.96 on the braking QP; the whole control cycle with ``auto`` takes 0.49-0.89
  of its time with ProxQP. The more rows bind, the larger DAQP's lead: from the last
  working set an active-set solve takes one or two steps of ``O(n^2)``, where ProxQP
  factorises its whole KKT system again; so the number of rows likely binding never
  tips the choice. The smallest QP (Panda, nothing binding) is where DAQP's per-call
  overhead shows most (0.89). Through qpsolvers, which rebuilds its workspace every
  call, DAQP takes 0.58-2.74 times ProxQP's time.
- Answers agree within 4e-7 rad/s on the weighted QPs and the second levels, but for
  BAZAR's second level once its joints are at their limits (2e-5; both solvers fail
  on some of those cycles, below). On a strict first level, singular but for the
  damping, ProxQP's tolerance leaves up to 4e-4 rad/s along the singular directions;
  DAQP's answer is exact there (within 1e-6 of quadprog's,
  ``tests/test_qp_backends.py``).
- Equality rows at least as many as the dofs (two more levels, out of reach): on
  BAZAR, with 28 and 31 rows for 16 dofs, DAQP found no answer on 74 and 209 of 600
  cycles, ProxQP on none; on Panda, 13 and 16 rows for 7 dofs, neither failed. With
  fewer rows than dofs (BAZAR's second level, 12 rows, joints at their limits) ProxQP
  failed on 122 cycles, DAQP on 99: DAQP keeps those levels.

A named solver (``proxqp``, ``daqp`` or a qpsolvers backend) overrides the rule.
"""

from __future__ import annotations

AUTO = "auto"
"""The name that asks for the rule."""


def choose(variables: int, equality_rows: int) -> str:
    """The backend the rule picks for a QP of ``variables`` (the dofs) and
    ``equality_rows``: ``"daqp"`` or ``"proxqp"``."""
    return "daqp" if equality_rows < variables else "proxqp"


def level_backends(dimensions: list[list[int]], dofs: int) -> list[str]:
    """The backend of every level of a hierarchy.

    Args:
        dimensions: The rows of every task of each level, highest priority first
            (each level's equality rows are the rows of the levels above it).
        dofs: Size of the command.
    """
    backends, above = [], 0
    for rows in dimensions:
        backends.append(choose(dofs, above))
        above += sum(rows)
    return backends
