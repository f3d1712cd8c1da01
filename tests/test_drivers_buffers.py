"""AsyncWorldReader / AsyncWorldWriter: consistent copies, thread ownership, shapes."""

import sys
import threading

import numpy as np
import pytest

from robocop_dsl.drivers import (AsyncWorldReader, AsyncWorldWriter, JointCommand,
                                 ThreadOwnershipError)
from robocop_dsl.world.world import JointGroup

CYCLES = 3000
PAIRS = 6


def big_group(name: str, dofs: int = 20000) -> JointGroup:
    """A group large enough that numpy copies take long and can interleave."""
    inf = np.full(dofs, np.inf)
    indices = np.arange(dofs)
    return JointGroup(name, tuple(f"j{i}" for i in range(dofs)), dofs, -inf, inf, inf, inf,
                      indices, indices)


@pytest.fixture
def fast_switching():
    """Make the interpreter switch threads as often as it can."""
    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    yield
    sys.setswitchinterval(interval)


def run_threads(targets) -> list:
    """Run each callable in its own thread; return the exceptions they raised."""
    errors = []

    def guard(target):
        try:
            target()
        except Exception as error:  # reported to the test thread
            errors.append(error)

    threads = [threading.Thread(target=guard, args=(t,)) for t in targets]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return errors


def state_pair(writer: AsyncWorldWriter, seen: list):
    """A driver thread publishing CYCLES states and a controller thread reading them."""
    size = writer.group.dofs

    def driver():
        for k in range(1, CYCLES + 1):
            writer.sync(np.full(size, float(k)), np.full(size, -float(k)), k % 2 == 1,
                        stamp=float(k))

    def controller():
        q, v = np.zeros(size), np.zeros(size)
        last = 0
        while last < CYCLES:
            state = writer.write(q, v)
            if state is None:
                continue
            k = state.sequence
            assert k >= last, "states went back in time"
            assert state.time == k and state.holding == (k % 2 == 1)
            assert np.all(state.position == k) and np.all(state.velocity == -k)
            assert np.all(q == k) and np.all(v == -k)
            seen.append(k)
            last = k

    return [driver, controller]


def command_pair(reader: AsyncWorldReader, seen: list):
    """A controller thread writing CYCLES commands and a driver thread taking them."""
    size = reader.group.dofs

    def controller():
        for k in range(1, CYCLES + 1):
            reader.read(np.full(size, float(k)))

    def driver():
        last = 0
        while last < CYCLES:
            command = reader.sync()
            if command is None:
                continue
            assert command.sequence >= last
            assert np.all(command.velocity == command.sequence)
            seen.append(command.sequence)
            last = command.sequence

    return [controller, driver]


def test_stress_many_threads_always_see_one_consistent_cycle(fast_switching):
    """Many buffer pairs hammered by their threads at once never show a torn copy."""
    targets, seen = [], []
    for i in range(PAIRS):
        targets += state_pair(AsyncWorldWriter(big_group(f"state{i}")), seen)
        targets += command_pair(AsyncWorldReader(big_group(f"command{i}")), seen)
    errors = run_threads(targets)
    assert errors == []
    assert seen.count(CYCLES) == 2 * PAIRS
    assert len(seen) > 2 * PAIRS * 10, "the consumers saw too few cycles to prove anything"


def test_stress_with_the_real_bazar_group(bazar, fast_switching):
    """The same check with the 16-dof group the BAZAR driver uses."""
    group = bazar.joint_group("bazar_upper_joints")
    seen = []
    errors = run_threads(state_pair(AsyncWorldWriter(group), seen)
                         + command_pair(AsyncWorldReader(group), seen))
    assert errors == [] and seen.count(CYCLES) == 2


def test_write_fills_only_the_group_coordinates(bazar):
    """write() puts the state at the group's indices of the world's q and v."""
    group = bazar.joint_group("bazar_ptu")
    writer = AsyncWorldWriter(group)
    q, v = np.full(bazar.model.nq, 7.0), np.full(bazar.model.nv, 7.0)
    assert writer.write(q, v) is None
    assert np.all(q == 7.0), "nothing is written before the first sync"
    errors = run_threads([lambda: writer.sync([0.1, 0.2], [1.0, 2.0], stamp=3.0)])
    assert errors == []
    state = writer.write(q, v)
    np.testing.assert_array_equal(q[group.q_indices], [0.1, 0.2])
    np.testing.assert_array_equal(v[group.v_indices], [1.0, 2.0])
    others = np.setdiff1d(np.arange(bazar.model.nq), group.q_indices)
    assert np.all(q[others] == 7.0)
    assert (state.sequence, state.time, state.holding) == (1, 3.0, False)


def test_copies_are_private_and_read_only():
    """What read()/sync() return is a frozen copy, not a view of the buffer."""
    reader = AsyncWorldReader(big_group("g", 3))
    source = np.array([1.0, 2.0, 3.0])
    written = reader.read(source)
    source[:] = 0.0
    taken = []
    assert run_threads([lambda: taken.append(reader.sync())]) == []
    command = taken[0]
    assert isinstance(command, JointCommand)
    np.testing.assert_array_equal(command.velocity, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(written.velocity, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError):
        command.velocity[0] = 5.0


def test_read_from_another_thread_is_refused():
    """Once a controller thread owns a side, another thread gets a clear error."""
    reader = AsyncWorldReader(big_group("arm", 2))
    reader.read([0.0, 0.0])
    errors = run_threads([lambda: reader.read([1.0, 1.0])])
    assert len(errors) == 1 and isinstance(errors[0], ThreadOwnershipError)
    message = str(errors[0])
    assert "AsyncWorldReader(arm, 2 dofs).read()" in message
    assert "MainThread" in message and "driver thread uses sync()" in message


def test_write_from_another_thread_is_refused():
    """The writer's write() belongs to the thread that first called it."""
    writer = AsyncWorldWriter(big_group("arm", 2))
    errors = run_threads([lambda: writer.write(np.zeros(2), np.zeros(2))])
    assert errors == []
    with pytest.raises(ThreadOwnershipError, match=r"write\(\) called from thread 'MainThread'"):
        writer.write(np.zeros(2), np.zeros(2))


def test_sync_belongs_to_one_driver_thread_until_released():
    """A second driver thread cannot sync until the first side is released."""
    writer = AsyncWorldWriter(big_group("arm", 1))
    assert run_threads([lambda: writer.sync([0.0], [0.0])]) == []
    errors = run_threads([lambda: writer.sync([1.0], [0.0])])
    assert len(errors) == 1 and "single thread feeding this buffer" in str(errors[0])
    writer.release_sync()
    assert run_threads([lambda: writer.sync([2.0], [0.0])]) == []
    assert writer.write(np.zeros(1), np.zeros(1)).position[0] == 2.0


def test_shapes_are_checked():
    """A vector of the wrong size names the buffer and the expected shape."""
    reader = AsyncWorldReader(big_group("arm", 3))
    with pytest.raises(ValueError, match=r"AsyncWorldReader\(arm, 3 dofs\): velocity must "
                                         r"have shape \(3,\), got \(2,\)"):
        reader.read([1.0, 2.0])
